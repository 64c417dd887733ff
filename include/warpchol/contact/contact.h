#pragma once

#include <warpchol/base/binary_io.h>
#include <warpchol/contact/friction_cone_solver.h>
#include <warpchol/fem/small_dense.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

/**
 * @file
 * One contact of the body's surface with an obstacle, what a contact step reports, and how
 * a checkpoint keeps a list of contacts: what the constraints (contact_constraints.h) and
 * the penalty springs (penalty_springs.h) share.
 */
namespace warpchol::fem
{
  /**
   * One contact: a surface vertex near an obstacle, or a point inside a surface triangle
   * near an instrument's tip (a sphere or a capsule) or an obstacle's sharp edge, which
   * would otherwise pass between the vertices.
   */
  struct Contact
  {
    /** The vertex (the triangle's first vertex for a point in a triangle). */
    unsigned int vertex   = 0;
    unsigned int obstacle = 0;
    /**
     * The point is sum_a weights[a] x(vertices[a]) over the first n_vertices: 1 for a
     * vertex (weight 1), 3 for a point in a triangle (its barycentric coordinates). Its
     * rows of H touch the 3 dofs of each.
     */
    unsigned int                n_vertices = 1;
    std::array<unsigned int, 3> vertices{};
    std::array<double, 3>       weights{{1, 0, 0}};

    /** The @p k-th vertex of the point (vertex itself for a vertex contact). */
    unsigned int vertex_of(const unsigned int k) const
    {
      return n_vertices == 1 ? vertex : vertices[k];
    }
    /** The obstacle's outward normal and two tangents (an orthonormal frame). */
    Vector3 normal, tangent_1, tangent_2;
    /** The signed distance (m) at the start of the step from the obstacle where it is at the step's end. */
    double gap = 0;
  };

  /** A field at @p contact's point: sum_a weights[a] field[vertices[a]]. */
  Vector3 point_value(const Contact &contact, const std::vector<Vector3> &field);

  /** (vertex, obstacle) as one number: how a contact is found again in the next step. */
  std::uint64_t contact_key(const Contact &contact);

  /** A checkpoint's list of contacts as the next step finds them again: vertex, obstacle, points. */
  void write_contact_keys(BinaryWriter &writer, const std::vector<Contact> &contacts);

  /** What write_contact_keys() wrote; fails naming @p what that does not fit @p n_obstacles. */
  std::vector<Contact> read_contact_keys(BinaryReader &reader, std::size_t n_obstacles, const std::string &what);

  /** What the last contact step did. */
  struct ContactStepReport
  {
    unsigned int n_contacts = 0;
    /** The contacts of each obstacle. */
    std::vector<unsigned int> contacts_per_obstacle;
    /** The largest penetration (m) after the step, over the contacts (0: none). */
    double       largest_penetration = 0;
    GaussSeidelResult gauss_seidel;
    /** Sums over the contacts of |normal force| and |friction force| (N). */
    double normal_force   = 0;
    double friction_force = 0;
    /** Sum of the contact forces (N), as a vector. */
    Vector3 total_force = Vector3::Zero();
    /** Work (J) of the contact impulses on the body in the step: lambda . H v(t+dt). */
    double work_on_body = 0;
    /** What friction dissipated (J, >= 0): -lambda_t . u_t, u_t the sliding velocity. */
    double friction_dissipation = 0;
    /**
     * The columns of L^-1 (one per unknown of a contact's vertex) W was built from: kept
     * from the step before (same factor, vertex still touching) and solved anew.
     */
    unsigned int kept_columns = 0, solved_columns = 0;
    /** The changes of the factor W lags behind (0: W is the factor's as it is). */
    unsigned int compliance_lag = 0;
    /**
     * With a lagged W, the largest difference (m/s) between the contacts' velocities after
     * the correction and those Gauss-Seidel aimed at, over their rows; times the step, a
     * distance. 0 where W is the factor's own (the direct solve goes where it aims).
     */
    double aim_error = 0;
  };
} // namespace warpchol::fem
