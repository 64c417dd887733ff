#include <warpchol/base/exceptions.h>
#include <warpchol/contact/obstacle.h>

#include <Eigen/Geometry>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace warpchol::fem
{
  namespace
  {
    using Kernel    = CGAL::Simple_cartesian<double>;
    using Point     = Kernel::Point_3;
    using Triangle  = Kernel::Triangle_3;
    using Iterator  = std::vector<Triangle>::const_iterator;
    using Primitive = CGAL::AABB_triangle_primitive<Kernel, Iterator>;
    using Tree      = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

    Vector3 to_vector(const Point &point)
    {
      return {point.x(), point.y(), point.z()};
    }

    /** A point's distance from a sphere's surface, and the normal there. */
    Proximity from_centre(const Vector3 &point, const Vector3 &centre, const double radius)
    {
      const Vector3 offset = point - centre;
      const double  length = offset.norm();
      return {length - radius, length > 0 ? Vector3(offset / length) : Vector3(Vector3::UnitZ())};
    }

    /** Points on a sphere of @p radius around @p centre, @p rings x @p sectors, and their triangles. */
    void add_sphere(TriangleSurface &surface, const Vector3 &centre, const double radius, const Vector3 &axis,
                    const double stretch)
    {
      const unsigned int rings = 8, sectors = 16;
      const auto         first = static_cast<unsigned int>(surface.points.size());
      // A frame with @p axis as its third direction (a capsule's shaft).
      const Vector3 u = axis.unitOrthogonal(), w = axis.cross(u);
      for (unsigned int r = 0; r <= rings; ++r)
        for (unsigned int s = 0; s < sectors; ++s)
          {
            const double theta = M_PI * r / rings, phi = 2 * M_PI * s / sectors;
            const double along = std::cos(theta);
            // The lower hemisphere at centre, the upper one shifted by stretch along the axis.
            surface.points.push_back(centre + radius * (std::sin(theta) * (std::cos(phi) * u + std::sin(phi) * w) +
                                                        along * axis) +
                                     (along > 0 || (along == 0 && r * 2 == rings) ? stretch : 0.) * axis);
          }
      for (unsigned int r = 0; r < rings; ++r)
        for (unsigned int s = 0; s < sectors; ++s)
          {
            const unsigned int a = first + r * sectors + s, b = first + r * sectors + (s + 1) % sectors;
            const unsigned int c = a + sectors, d = b + sectors;
            surface.triangles.push_back({{a, c, b}});
            surface.triangles.push_back({{b, c, d}});
          }
    }
  } // namespace

  struct Obstacle::SurfaceTree
  {
    TriangleSurface       surface;
    std::vector<Triangle> triangles;
    Tree                  tree;
    /** The points of triangles[i]; the pseudonormals of the points and of the edges (unnormalized). */
    std::vector<std::array<unsigned int, 3>>                    corners;
    std::vector<Vector3>                                        point_normals;
    std::map<std::pair<unsigned int, unsigned int>, Vector3>    edge_normals;

    /** The normal that tells the side of a point whose closest point is @p closest on triangles[@p i]. */
    Vector3 side_normal(std::size_t i, const Vector3 &closest) const;
  };

  Vector3 Obstacle::SurfaceTree::side_normal(const std::size_t i, const Vector3 &closest) const
  {
    // The closest point's barycentric coordinates: inside the triangle, its own normal;
    // on an edge, the edge's; at a corner, the point's.
    const auto    &t = corners[i];
    const Vector3 &a = surface.points[t[0]], &b = surface.points[t[1]], &c = surface.points[t[2]];
    const Vector3  normal = (b - a).cross(c - a);
    const double   area   = normal.squaredNorm();
    const std::array<double, 3> weight{(c - b).cross(closest - b).dot(normal) / area,
                                       (a - c).cross(closest - c).dot(normal) / area,
                                       (b - a).cross(closest - a).dot(normal) / area};
    constexpr double on_side = 1e-9;
    int              n_zero = 0, zero = 0, other = 0;
    for (int k = 0; k < 3; ++k)
      if (weight[k] <= on_side)
        ++n_zero, zero = k;
      else
        other = k;
    if (n_zero == 1)
      return edge_normals.at(std::minmax(t[(zero + 1) % 3], t[(zero + 2) % 3]));
    if (n_zero == 2)
      return point_normals[t[other]];
    return normal;
  }

  Obstacle Obstacle::plane(const Vector3 &point, const Vector3 &normal)
  {
    if (!(normal.norm() > 0))
      throw InputError("a plane's normal must not be zero");
    Obstacle obstacle;
    obstacle.kind   = ObstacleShape::plane;
    obstacle.first  = point;
    obstacle.second = normal.normalized();
    return obstacle;
  }

  Obstacle Obstacle::sphere(const Vector3 &centre, const double radius)
  {
    if (!(radius > 0))
      throw InputError("a sphere's radius must be positive");
    Obstacle obstacle;
    obstacle.kind   = ObstacleShape::sphere;
    obstacle.first  = centre;
    obstacle.radius = radius;
    return obstacle;
  }

  Obstacle Obstacle::capsule(const Vector3 &end_a, const Vector3 &end_b, const double radius)
  {
    if (!(radius > 0))
      throw InputError("a capsule's radius must be positive");
    Obstacle obstacle;
    obstacle.kind   = ObstacleShape::capsule;
    obstacle.first  = end_a;
    obstacle.second = end_b;
    obstacle.radius = radius;
    return obstacle;
  }

  Obstacle Obstacle::box(const Vector3 &centre, const Vector3 &size)
  {
    if (!(size.minCoeff() > 0))
      throw InputError("a box's edges must be positive");
    Obstacle obstacle;
    obstacle.kind   = ObstacleShape::box;
    obstacle.first  = centre;
    obstacle.second = size / 2;
    // Each edge joins two corners that differ in one coordinate.
    for (int axis = 0; axis < 3; ++axis)
      for (int corner = 0; corner < 8; ++corner)
        if (((corner >> axis) & 1) == 0)
          {
            Vector3 from, to;
            for (int d = 0; d < 3; ++d)
              from[d] = centre[d] + (((corner >> d) & 1) ? 1 : -1) * obstacle.second[d];
            to       = from;
            to[axis] = centre[axis] + obstacle.second[axis];
            obstacle.edges_at_rest.push_back({from, to});
          }
    return obstacle;
  }

  Obstacle Obstacle::surface(TriangleSurface triangles)
  {
    auto tree = std::make_shared<SurfaceTree>();
    tree->surface = std::move(triangles);
    const auto &points = tree->surface.points;
    // Per edge the unit normals of its triangles; per point the angle-weighted sum of
    // theirs (Baerentzen and Aanaes' pseudonormals, which tell inside from outside off an
    // edge or a corner, where the closest triangle's own plane may not).
    std::map<std::pair<unsigned int, unsigned int>, std::vector<Vector3>> normals_at_edge;
    tree->point_normals.assign(points.size(), Vector3::Zero());
    for (const auto &t : tree->surface.triangles)
      {
        const Vector3 &a = points[t[0]], &b = points[t[1]], &c = points[t[2]];
        const Vector3  normal = (b - a).cross(c - a);
        // Triangles of no area have no side: CGAL's tree would return them as closest.
        if (!(normal.norm() > 0))
          continue;
        tree->triangles.emplace_back(Point(a[0], a[1], a[2]), Point(b[0], b[1], b[2]), Point(c[0], c[1], c[2]));
        tree->corners.push_back(t);
        for (int k = 0; k < 3; ++k)
          {
            const Vector3 &at = points[t[k]], &next = points[t[(k + 1) % 3]], &last = points[t[(k + 2) % 3]];
            const double   cosine = (next - at).normalized().dot((last - at).normalized());
            tree->point_normals[t[k]] += std::acos(std::clamp(cosine, -1., 1.)) * normal.normalized();
            normals_at_edge[std::minmax(t[k], t[(k + 1) % 3])].push_back(normal.normalized());
          }
      }
    // The sharp edges: those of one triangle, or between two whose normals part by more
    // than sharp_edge_degrees (an edge of more than two triangles is sharp too).
    const double         flat = std::cos(sharp_edge_degrees * M_PI / 180);
    std::vector<Segment> edges;
    for (const auto &[edge, normals] : normals_at_edge)
      {
        Vector3 sum = Vector3::Zero();
        for (const Vector3 &normal : normals)
          sum += normal;
        tree->edge_normals[edge] = sum;
        if (normals.size() != 2 || normals[0].dot(normals[1]) < flat)
          edges.push_back({points[edge.first], points[edge.second]});
      }
    tree->tree.insert(tree->triangles.begin(), tree->triangles.end());
    tree->tree.build();
    tree->tree.accelerate_distance_queries();
    Obstacle obstacle;
    obstacle.kind          = ObstacleShape::surface;
    obstacle.tree          = std::move(tree);
    obstacle.edges_at_rest = std::move(edges);
    return obstacle;
  }

  ObstacleShape Obstacle::shape() const
  {
    return kind;
  }

  void Obstacle::set_friction(const double friction_coefficient)
  {
    if (!(friction_coefficient >= 0))
      throw InputError("a friction coefficient must be a number >= 0");
    coefficient = friction_coefficient;
  }

  double Obstacle::friction() const
  {
    return coefficient;
  }

  void Obstacle::set_path(InstrumentPath instrument_path)
  {
    if (!instrument_path.empty() && instrument_path.values_per_sample() != 3 &&
        instrument_path.values_per_sample() != 6)
      throw Error("an obstacle's path has 3 values a sample (x, y, z) or 6 (and a rotation vector)");
    path = std::move(instrument_path);
  }

  Vector3 Obstacle::Pose::from_rest(const Vector3 &point) const
  {
    return rotation * (point - start) + position;
  }

  Vector3 Obstacle::Pose::to_rest(const Vector3 &point) const
  {
    return rotation.transpose() * (point - position) + start;
  }

  Obstacle::Pose Obstacle::pose(const double time) const
  {
    Pose pose;
    if (path.empty())
      return pose;
    pose.start    = path.position(path.start_time());
    pose.position = path.position(time);
    if (path.values_per_sample() < 6)
      return pose;
    const auto turn = [](const Vector3 &vector) -> Matrix3 {
      const double angle = vector.norm();
      return angle > 0 ? Eigen::AngleAxisd(angle, vector / angle).toRotationMatrix() : Matrix3::Identity();
    };
    // Relative to the first sample's rotation: the obstacle is given where the path starts.
    pose.rotation = turn(path.position(time, 3)) * turn(path.position(path.start_time(), 3)).transpose();
    return pose;
  }

  Vector3 Obstacle::velocity(const Vector3 &point, const double from, const double to) const
  {
    return (pose(to).from_rest(pose(from).to_rest(point)) - point) / (to - from);
  }

  Proximity Obstacle::proximity(const Vector3 &point, const double time) const
  {
    const Pose at        = pose(time);
    Proximity  proximity = proximity_at_rest(at.to_rest(point));
    proximity.normal     = at.rotation * proximity.normal;
    return proximity;
  }

  std::vector<Obstacle::Segment> Obstacle::sharp_edges(const double time) const
  {
    const Pose           at    = pose(time);
    std::vector<Segment> edges = edges_at_rest;
    for (Segment &edge : edges)
      for (Vector3 &end : edge)
        end = at.from_rest(end);
    return edges;
  }

  Vector3 Obstacle::core_point(const Vector3 &point, const double time) const
  {
    const Pose at = pose(time);
    if (kind == ObstacleShape::sphere)
      return at.from_rest(first);
    if (kind != ObstacleShape::capsule)
      throw Error("core_point(): only spheres and capsules have a core");
    const Vector3 axis   = second - first;
    const double  length = axis.squaredNorm();
    const double  along  = length > 0 ? std::clamp((at.to_rest(point) - first).dot(axis) / length, 0., 1.) : 0.;
    return at.from_rest(first + along * axis);
  }

  Proximity Obstacle::proximity_at_rest(const Vector3 &point) const
  {
    switch (kind)
      {
        case ObstacleShape::plane:
          return {second.dot(point - first), second};
        case ObstacleShape::sphere:
          return from_centre(point, first, radius);
        case ObstacleShape::capsule:
          {
            const Vector3 axis   = second - first;
            const double  length = axis.squaredNorm();
            const double  along  = length > 0 ? std::clamp((point - first).dot(axis) / length, 0., 1.) : 0.;
            return from_centre(point, first + along * axis, radius);
          }
        case ObstacleShape::box:
          {
            const Vector3 local = point - first;
            const Vector3 q     = local.cwiseAbs() - second;
            if (q.maxCoeff() > 0)
              {
                // Outside: the distance to the closest point of the box.
                const Vector3 outside = q.cwiseMax(0.);
                Vector3       normal  = outside.cwiseProduct(local.cwiseSign());
                const double  length  = normal.norm();
                return {length, normal / length};
              }
            // Inside: the nearest face.
            Eigen::Index axis = 0;
            q.maxCoeff(&axis);
            Vector3 normal  = Vector3::Zero();
            normal[axis]    = local[axis] >= 0 ? 1. : -1.;
            return {q[axis], normal};
          }
        case ObstacleShape::surface:
          {
            const auto [closest, triangle] = tree->tree.closest_point_and_primitive(Point(point[0], point[1], point[2]));
            const Vector3 face_normal = to_vector(CGAL::ORIGIN + triangle->supporting_plane().orthogonal_vector()).normalized();
            const Vector3 offset      = point - to_vector(closest);
            const double  length      = offset.norm();
            const Vector3 side_normal =
              tree->side_normal(static_cast<std::size_t>(triangle - tree->triangles.begin()), to_vector(closest));
            const double side = offset.dot(side_normal) >= 0 ? 1. : -1.;
            // Off an edge or a corner the normal is the direction to the closest point.
            const Vector3 normal = length > 1e-12 ? Vector3(side * offset / length) : face_normal;
            return {side * length, normal};
          }
      }
    return {};
  }

  TriangleSurface Obstacle::boundary(const double time, const double plane_size) const
  {
    TriangleSurface surface;
    switch (kind)
      {
        case ObstacleShape::plane:
          {
            const Vector3 u = second.unitOrthogonal() * plane_size / 2, w = second.cross(u);
            surface.points    = {first - u - w, first + u - w, first + u + w, first - u + w};
            surface.triangles = {{{0, 1, 2}}, {{0, 2, 3}}};
            break;
          }
        case ObstacleShape::sphere:
          add_sphere(surface, first, radius, Vector3::UnitZ(), 0);
          break;
        case ObstacleShape::capsule:
          {
            const Vector3 axis = second - first;
            const double  length = axis.norm();
            add_sphere(surface, first, radius, length > 0 ? Vector3(axis / length) : Vector3(Vector3::UnitZ()), length);
            break;
          }
        case ObstacleShape::box:
          {
            for (unsigned int corner = 0; corner < 8; ++corner)
              surface.points.push_back(first + Vector3(corner & 1 ? second[0] : -second[0],
                                                       corner & 2 ? second[1] : -second[1],
                                                       corner & 4 ? second[2] : -second[2]));
            // Two triangles per face, corners counter-clockwise seen from outside.
            surface.triangles = {{{0, 2, 3}}, {{0, 3, 1}}, {{4, 5, 7}}, {{4, 7, 6}}, {{0, 1, 5}}, {{0, 5, 4}},
                                 {{2, 6, 7}}, {{2, 7, 3}}, {{0, 4, 6}}, {{0, 6, 2}}, {{1, 3, 7}}, {{1, 7, 5}}};
            break;
          }
        case ObstacleShape::surface:
          surface = tree->surface;
          break;
      }
    const Pose at = pose(time);
    for (Vector3 &point : surface.points)
      point = at.from_rest(point);
    return surface;
  }
} // namespace warpchol::fem
