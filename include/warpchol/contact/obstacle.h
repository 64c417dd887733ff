#pragma once

#include <warpchol/base/named_values.h>
#include <warpchol/contact/triangle_surface.h>
#include <warpchol/fem/small_dense.h>
#include <warpchol/surgery/instrument_path.h>

#include <array>
#include <memory>

/**
 * @file
 * Rigid obstacles and instruments the body touches: a plane (a table), a sphere (a probe's
 * tip), a capsule (an instrument's shaft and tip), a box, and a triangle surface read from
 * a file (triangle_surface.h). Each is fixed or moved along an instrument path: translated,
 * and rotated too if the path gives rotations.
 *
 * Proximity: the analytic shapes by their closed-form signed distance; a triangle surface
 * by CGAL's AABB tree (libcgal-dev, header-only with Simple_cartesian<double>): a
 * well-kept library whose closest-point query returns the triangle too, which gives the
 * side; FCL's distance queries want a second collision object and return no sign, and
 * deal.II's Boost R-tree indexes boxes, not triangles.
 */
namespace warpchol::fem
{
  /** The kinds of obstacles. */
  enum class ObstacleShape
  {
    plane,
    sphere,
    capsule,
    box,
    surface
  };

  /** Their names (base/named_values.h). */
  inline constexpr NameTable<ObstacleShape, 5> obstacle_shape_names{{{ObstacleShape::plane, "plane"},
                                                                     {ObstacleShape::sphere, "sphere"},
                                                                     {ObstacleShape::capsule, "capsule"},
                                                                     {ObstacleShape::box, "box"},
                                                                     {ObstacleShape::surface, "surface"}}};

  /** Where a point is relative to an obstacle's surface. */
  struct Proximity
  {
    /** Signed distance to the surface (m): positive outside, negative inside. */
    double  distance = 0;
    /** The unit normal of the surface at the closest point, pointing out of the obstacle. */
    Vector3 normal = Vector3::UnitZ();
  };

  /**
   * A rigid obstacle: its shape at rest, its friction coefficient (Coulomb's, static =
   * dynamic) and, if it moves, the path that moves it from its rest (set_path()).
   */
  class Obstacle
  {
  public:
    /** The half-space below the plane through @p point with outward @p normal. */
    static Obstacle plane(const Vector3 &point, const Vector3 &normal);
    static Obstacle sphere(const Vector3 &centre, double radius);
    /** The points within @p radius of the segment from @p end_a to @p end_b. */
    static Obstacle capsule(const Vector3 &end_a, const Vector3 &end_b, double radius);
    /** The axis-aligned box of centre @p centre and edge lengths @p size. */
    static Obstacle box(const Vector3 &centre, const Vector3 &size);
    /**
     * A triangle surface: a point is inside when it lies behind the closest triangle
     * (against its normal, from the order of its corners). A closed, consistently
     * oriented surface has its inside where its triangles face away.
     */
    static Obstacle surface(TriangleSurface triangles);

    ObstacleShape shape() const;

    void   set_friction(double coefficient);
    double friction() const;

    /**
     * Move the obstacle along @p path, which starts where the obstacle is at rest. With 3
     * values a sample (x, y, z), p(t) translates it by p(t) - p(t0); with 6 (x, y, z, and a
     * rotation vector r in radians, linear in between samples: exact for a fixed axis) a
     * point x at rest is at R(t) (x - p(t0)) + p(t) at time t, R(t) = exp(r(t)) exp(r(t0))^T:
     * it turns about the path's point. Throws Error for another number of values.
     */
    void set_path(InstrumentPath path);

    /**
     * The mean velocity from @p from to @p to of the obstacle's point that is at @p point
     * at @p from (the velocity a contact there moves with).
     */
    Vector3 velocity(const Vector3 &point, double from, double to) const;

    /** The signed distance and normal of @p point at @p time. */
    Proximity proximity(const Vector3 &point, double time) const;

    /**
     * For the shapes that are a core grown by a radius, the point of the core nearest
     * @p point at @p time: a sphere's centre, the point of a capsule's axis. The deepest
     * point of a flat triangle in such an obstacle is the triangle's point nearest it.
     * Throws Error for the other shapes.
     */
    Vector3 core_point(const Vector3 &point, double time) const;

    /** A segment of an obstacle's boundary: its two ends. */
    using Segment = std::array<Vector3, 2>;

    /**
     * The sharp edges at @p time, which a flat triangle of the body can pass over between
     * its vertices: a box's 12; a triangle surface's edges that border one triangle, or
     * where two meet at more than sharp_edge_degrees. None for the plane, and for the
     * shapes grown from a core (core_point() serves them).
     */
    std::vector<Segment> sharp_edges(double time) const;

    /** Faces of a triangle surface that meet at more than this angle make a sharp edge. */
    static constexpr double sharp_edge_degrees = 30;

    /**
     * The surface at @p time as triangles, for output: the analytic shapes tessellated, a
     * plane as a square of side @p plane_size around its point.
     */
    TriangleSurface boundary(double time, double plane_size = 1) const;

  private:
    Obstacle() = default;

    /** The proximity of the obstacle at rest. */
    Proximity proximity_at_rest(const Vector3 &point) const;
    /** Where set_path() has the obstacle at a time: x at rest is at R (x - p(t0)) + p(t). */
    struct Pose
    {
      Matrix3 rotation = Matrix3::Identity();
      Vector3 start = Vector3::Zero(), position = Vector3::Zero();

      /** Where the point @p point of the obstacle at rest is. */
      Vector3 from_rest(const Vector3 &point) const;
      /** Where the point at @p point is when the obstacle is at rest. */
      Vector3 to_rest(const Vector3 &point) const;
    };
    /** The pose at @p time (the rest pose without a path), once per query: the rotation costs two turns. */
    Pose pose(double time) const;

    ObstacleShape  kind = ObstacleShape::plane;
    /** plane: point; sphere, box: centre; capsule: one end. */
    Vector3        first = Vector3::Zero();
    /** plane: normal; capsule: the other end; box: half the edge lengths. */
    Vector3        second = Vector3::Zero();
    double         radius = 0;
    double         coefficient = 0;
    InstrumentPath path;
    /** sharp_edges() where the obstacle is at rest (a box's, a triangle surface's). */
    std::vector<Segment> edges_at_rest;
    /** The triangle surface and its AABB tree (shared: an obstacle is copied with its tree). */
    struct SurfaceTree;
    std::shared_ptr<const SurfaceTree> tree;
  };
} // namespace warpchol::fem
