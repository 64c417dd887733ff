#include <warpchol/surgery/blade.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace warpchol::fem
{
  std::pair<Vector3, Vector3> Blade::edge_at(const double time) const
  {
    const double moving = std::clamp(time - begin, 0., duration);
    if (!path.empty())
      return {path.position(begin + moving, 0), path.position(begin + moving, 3)};
    const Vector3 offset = moving * velocity;
    return {start + offset, end + offset};
  }

  bool Blade::moves_during(const double from, const double to) const
  {
    return (velocity.norm() > 0 || !path.empty()) && to > begin && from < begin + duration;
  }

  namespace
  {
    /** The interval of the projections of @p points onto @p axis. */
    template <std::size_t n>
    std::pair<double, double> projection(const std::array<Vector3, n> &points, const Vector3 &axis)
    {
      double low = std::numeric_limits<double>::infinity(), high = -low;
      for (const Vector3 &point : points)
        {
          const double value = point.dot(axis);
          low                = std::min(low, value);
          high               = std::max(high, value);
        }
      return {low, high};
    }
  } // namespace

  bool tetrahedron_meets_triangle(const std::array<Vector3, 4> &tetrahedron, const std::array<Vector3, 3> &triangle)
  {
    // The size of the pair: what "touching only" is measured against.
    double size = 0;
    for (const auto &p : tetrahedron)
      for (const auto &q : triangle)
        size = std::max(size, (p - q).norm());
    const double tolerance = 1e-12 * size;

    std::array<Vector3, 6> tetrahedron_edges;
    unsigned int           k = 0;
    for (unsigned int a = 0; a < 4; ++a)
      for (unsigned int b = a + 1; b < 4; ++b)
        tetrahedron_edges[k++] = tetrahedron[b] - tetrahedron[a];
    const std::array<Vector3, 3> triangle_edges{
      {triangle[1] - triangle[0], triangle[2] - triangle[1], triangle[0] - triangle[2]}};

    // The triangle's normal, the 4 face normals, the 18 cross products of edges.
    std::array<Vector3, 23> axes;
    unsigned int            n_axes = 0;
    axes[n_axes++]                 = triangle_edges[0].cross(triangle_edges[1]);
    const unsigned int faces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
    for (const auto &face : faces)
      axes[n_axes++] = (tetrahedron[face[1]] - tetrahedron[face[0]]).cross(tetrahedron[face[2]] - tetrahedron[face[0]]);
    for (const Vector3 &u : triangle_edges)
      for (const Vector3 &w : tetrahedron_edges)
        axes[n_axes++] = u.cross(w);
    for (const Vector3 &axis : axes)
      {
        const double length = axis.norm();
        if (!(length > 1e-14 * size * size))
          continue; // parallel edges, a flat triangle: no axis
        const Vector3 unit             = axis / length;
        const auto [tet_low, tet_high] = projection(tetrahedron, unit);
        const auto [tri_low, tri_high] = projection(triangle, unit);
        if (tet_high <= tri_low + tolerance || tri_high <= tet_low + tolerance)
          return false;
      }
    return true;
  }

  std::vector<unsigned int> elements_crossed(const ElasticBody &body, const std::vector<Vector3> &positions,
                                             const Blade &blade, const double from, const double to,
                                             const std::vector<bool> &cut)
  {
    std::vector<unsigned int> crossed;
    if (!blade.moves_during(from, to))
      return crossed;
    // The times the edge bends at: the step's ends and the path's samples between them.
    std::vector<double> times{from};
    if (!blade.path.empty())
      for (const double t : blade.path.times_between(std::max(from, blade.begin),
                                                     std::min(to, blade.begin + blade.duration)))
        times.push_back(t);
    times.push_back(to);
    // Each stretch sweeps the quadrilateral a0 b0 b1 a1: two triangles; and their bounding box.
    std::vector<std::array<Vector3, 3>> triangles;
    Vector3 low  = Vector3::Constant(std::numeric_limits<double>::infinity());
    Vector3 high = -low;
    for (std::size_t k = 0; k + 1 < times.size(); ++k)
      {
        const auto [a0, b0] = blade.edge_at(times[k]);
        const auto [a1, b1] = blade.edge_at(times[k + 1]);
        if (a0 == a1 && b0 == b1)
          continue; // the edge holds still: it sweeps nothing
        triangles.push_back({{a0, b0, b1}});
        triangles.push_back({{a0, b1, a1}});
        low  = low.cwiseMin(a0).cwiseMin(b0).cwiseMin(a1).cwiseMin(b1);
        high = high.cwiseMax(a0).cwiseMax(b0).cwiseMax(a1).cwiseMax(b1);
      }
    if (triangles.empty())
      return crossed;
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      {
        if (cut[e])
          continue;
        std::array<Vector3, 4> tetrahedron;
        Vector3                tet_low  = Vector3::Constant(std::numeric_limits<double>::infinity());
        Vector3                tet_high = -tet_low;
        for (unsigned int a = 0; a < 4; ++a)
          {
            tetrahedron[a] = positions[body.element_vertices(e)[a]];
            tet_low        = tet_low.cwiseMin(tetrahedron[a]);
            tet_high       = tet_high.cwiseMax(tetrahedron[a]);
          }
        if ((tet_high.array() < low.array()).any() || (tet_low.array() > high.array()).any())
          continue;
        if (std::any_of(triangles.begin(), triangles.end(), [&](const std::array<Vector3, 3> &triangle) {
              return tetrahedron_meets_triangle(tetrahedron, triangle);
            }))
          crossed.push_back(e);
      }
    return crossed;
  }
} // namespace warpchol::fem
