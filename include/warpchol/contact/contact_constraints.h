#pragma once

#include <warpchol/base/binary_io.h>
#include <warpchol/cholesky/compliance.h>
#include <warpchol/contact/contact.h>
#include <warpchol/contact/contact_compliance.h>
#include <warpchol/contact/friction_cone_solver.h>
#include <warpchol/contact/obstacle.h>
#include <warpchol/contact/penalty_springs.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/models/elasticity_model.h>

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

/**
 * @file
 * Contact of the body's surface with rigid obstacles, solved as SOFA solves it
 * (GenericConstraintSolver with LinearSolverConstraintCorrection): the step's free motion
 * first, then a correction by impulses on the contacts' rows.
 */
namespace warpchol::fem
{
  /** The stages of a contact step, as StepStatistics::stages names them. */
  namespace stage
  {
    /** The body's surface vertices against the obstacles. */
    constexpr const char *contact_detection = "contact detection";
    /** W = H A^-1 H^T from the factor (cholesky/compliance.h). */
    constexpr const char *contact_compliance = "contact compliance";
    /** Projected Gauss-Seidel on W. */
    constexpr const char *contact_gauss_seidel = "contact Gauss-Seidel";
    /** The correction v += A^-1 H^T lambda (one solve). */
    constexpr const char *contact_correction = "contact correction";
    /** Penalty contact: the springs tied and untied, their forces, the penetration after the step. */
    constexpr const char *contact_penalty = "contact penalty";
  } // namespace stage

  /**
   * The vertices on the surface of @p body (sorted): those of the faces that belong to one
   * element only of those not cut, so that a cut's new faces are surface and a cut
   * element touches nothing.
   */
  std::vector<unsigned int> surface_vertices(const ElasticBody &body);

  /** The faces on the surface of @p body (each once, its vertices sorted), as surface_vertices() finds them. */
  std::vector<std::array<unsigned int, 3>> surface_triangles(const ElasticBody &body);

  /**
   * Why @p obstacle is inside the body at the start, or "" if it is not: a vertex of the
   * free surface at @p positions more than @p tolerance inside it, or its reference point
   * (the centre of its boundary's points) inside an element that is not cut. A plane has
   * no inside point to check but the vertices.
   */
  std::string obstacle_inside_body(const Obstacle &obstacle, const ElasticBody &body,
                                   const std::vector<Vector3> &positions, double tolerance);

  /**
   * How contact pushes back: constraints (SOFA's way: impulses by Gauss-Seidel on W, one
   * correcting solve), or penalty springs carried in A and its factor (rank-k updates and
   * downdates as contacts come and go).
   */
  enum class ContactMethod
  {
    constraints,
    penalty
  };

  /** What the contact step is told. */
  struct ContactSettings
  {
    ContactMethod method = ContactMethod::constraints;
    /**
     * Penalty: the stiffness (N/m) of the spring a contact about to penetrate gets. Its force
     * pushes along the obstacle's normal, k times the penetration; in A it adds dt^2 k to
     * the vertex's 3 diagonal entries (as the grasps' springs: the same in every rotated
     * frame, so a change of the diagonal the factor takes as an update), which also drags
     * the vertex along the obstacle's surface as a viscous friction of coefficient dt k.
     */
    double penalty_stiffness = 1e5;
    /** A surface vertex within this distance (m) of an obstacle is a contact (besides how far it may move in a step). */
    double margin = 1e-3;
    /** The penetration (m) a step may leave: the largest one is checked against it. */
    double tolerance = 1e-4;
    GaussSeidelSettings gauss_seidel;
    /** More contacts than this in a step is an error (the size of W grows as their square). */
    unsigned int max_contacts = 1000;
    /** Where the cap is set, for the message ("FILE:LINE: Contact/Max contacts"). */
    std::string  max_contacts_origin = "Contact/Max contacts";
    /** Where Gauss-Seidel's iterations are set, for the warning when it stops short. */
    std::string  max_iterations_origin = "Contact/Max iterations";
    /** Where the penetration's tolerance is set, for the warning when penalty springs pass it. */
    std::string  tolerance_origin = "Contact/Contact distance";
    /**
     * How W is built from the factor: by paths, from the block of A^-1 among the contact
     * vertices' unknowns with the columns of the vertices that persist kept
     * (SparseCholesky::inverse_block()); by full solves, SOFA's way (the peer).
     */
    cholesky::ComplianceMethod compliance = cholesky::ComplianceMethod::paths;
    /**
     * By paths, with direct solves: the kept columns of A^-1 outlive the factor's changes
     * (a re-rotation's partial refactorization, an update), so that W lags behind the
     * factor, and the correction, by the factor as it is, checks it: a step whose contacts
     * end further than a quarter of the tolerance from where Gauss-Seidel aimed them is
     * solved again from there, and W is renewed once such rounds have cost about a
     * renewal. Gauss-Seidel then stops at a tenth of the miss the check allows, if that
     * is above its tolerance. False: W is renewed at every change of the factor.
     */
    bool keep_compliance_across_factor_changes = false;
  };

  /**
   * The obstacles and the contact step of one body. For a step with free velocities
   * v_free (the implicit Euler step without contact, A~ v_free = b with
   * A~ = R A R^T): the contacts at x(t) (detect()), the compliance
   *   W = H A~^-1 H^T = (H R) A^-1 (H R)^T
   * from the factor of A (compliance_from_kept_columns(), the rows of H rotated by
   * R^T, 3 unknowns per contact vertex), the impulses lambda by projected Gauss-Seidel with
   * the friction cone, and the correction v = v_free + A~^-1 H^T lambda (one solve with
   * the model). A contact's normal row asks for n . v(t+dt) >= -gap / dt, so that the next
   * position is outside the obstacle to first order (no Baumgarte term); the tangents slide
   * relative to the obstacle's velocity.
   *
   * Where the model's solve iterates (WCC's CG on a stale factor), W comes from that
   * factor: the preconditioner's compliance, not A's; the correction is the model's own
   * solve (exact to CG's tolerance), so a stale W only makes Gauss-Seidel aim slightly
   * off (contact_compliance_from_stale_factor measures by how much).
   */
  class ContactConstraints
  {
  public:
    ContactConstraints(std::vector<Obstacle> obstacles, const ContactSettings &settings);

    /** Throw InputError naming the obstacle (from 1) if it is inside the body at time 0 (obstacle_inside_body()). */
    void check_start(const ElasticBody &body, const std::vector<Vector3> &positions) const;

    /**
     * The contacts of the vertices on the body's surface (faces of one element that is not
     * cut: a cut's new faces are surface, a cut element touches nothing) at @p positions,
     * the obstacles where they are at @p time, within the margin plus how far
     * @p velocities move a vertex in @p time_step.
     */
    std::vector<Contact> detect(const ElasticBody &body, const std::vector<Vector3> &positions,
                                const std::vector<Vector3> &velocities, double time, double time_step);

    /**
     * The contact step: @p velocities holds the free velocities at time @p time (the
     * step's start) on entry, the corrected ones on exit. Throws InputError if more
     * contacts than ContactSettings::max_contacts touch.
     */
    void correct(const ElasticBody &body, ElasticityModel &model, const std::vector<Vector3> &positions,
                 std::vector<Vector3> &velocities, double time, double time_step, StepStatistics &statistics);

    const std::vector<Obstacle> &obstacles() const;
    const ContactSettings       &settings() const;
    const ContactStepReport     &last_step() const;
    /** Totals over the steps so far: the contact impulses' work on the body, friction's dissipation. */
    double work_on_body() const;
    double friction_dissipation() const;
    /** The contact force (N) on each vertex in the last step (zero off the contacts). */
    const std::vector<Vector3> &vertex_forces() const;
    /** The gap (m) of each vertex after the last step: its distance to the nearest obstacle, up to the margin. */
    const std::vector<double> &vertex_gaps() const;
    /** The contacts of the last step. */
    const std::vector<Contact> &contacts() const;

    /**
     * Write to a checkpoint what the next steps read: the last step's contacts as the warm
     * start finds them again (vertex, obstacle, a vertex or a point in a triangle), their
     * impulses, and the totals of the contact work and friction's dissipation. The kept
     * columns of L^-1 are not written: they are dropped, so that this run solves them anew
     * at its next step as the resumed one does (a lagged W would make the two differ).
     */
    void save(BinaryWriter &writer) const;
    /** Read what save() wrote; fails naming what does not fit these obstacles. */
    void load(BinaryReader &reader);

    /**
     * @name Penalty contact (ContactMethod::penalty, PenaltySprings)
     *
     * Before the step: the contacts at @p positions (detect()) and the springs they tie or
     * keep (PenaltySprings::tie()); the changed diagonal goes to A and its factor with the
     * step's system change. Then add_penalty_forces() adds the springs' forces to the
     * step's; after a solve, tie_entering_springs() ties what the step's acceleration
     * carried in (the step is then solved again), and finish_penalty_step() records
     * forces, gaps, penetration and work.
     */
    /** @{ */
    PenaltySprings::Change tie_penalty_springs(const ElasticBody &body, const std::vector<Vector3> &positions,
                                               const std::vector<Vector3> &velocities, double time, double time_step,
                                               StepStatistics &statistics);
    PenaltySprings::Change tie_entering_springs(const std::vector<Vector3> &positions,
                                                const std::vector<Vector3> &velocities, double time, double time_step,
                                                StepStatistics &statistics);
    /** The diagonal dt^2 sum k w of the springs on @p vertex now (0 without one). */
    double penalty_diagonal(unsigned int vertex) const;
    void   add_penalty_forces(std::vector<Vector3> &forces) const;
    void   finish_penalty_step(const std::vector<Vector3> &positions, const std::vector<Vector3> &velocities,
                               double time, double time_step, StepStatistics &statistics);
    /** @} */

    /** H^T (A's unknowns x 3 contacts) for @p contacts, rotated by @p rotations (null: identity). */
    static sparse::CSCMatrix constraint_columns(const ElasticBody &body, const std::vector<Contact> &contacts,
                                                const std::vector<Matrix3> *rotations);

  private:
    /** The step's contacts (detect()) into step_contacts, counted in the report; throws InputError past the cap. */
    void detect_for_step(const ElasticBody &body, const std::vector<Vector3> &positions,
                         const std::vector<Vector3> &velocities, double time, double time_step,
                         StepStatistics &statistics);

    /**
     * W = H A~^-1 H^T of the step's contacts, factored as D^T G D with G the block of A^-1
     * among their vertices' unknowns (SparseCholesky::inverse_block(), which keeps the
     * columns of the vertices that persist while the factor does not change): W's 3 x 3
     * block of contacts i and j is the sum over their vertices u, v of D_iu^T G_uv D_jv,
     * D_iu = w_iu R_u^T [n t_1 t_2] (the contact's directions, its weight on u, the nodal
     * rotation). It reads kept_columns' G: valid until the next call. With @p lag the
     * kept columns outlive the factor's changes (KeptInverseColumns).
     */
    ContactCompliance compliance_from_kept_columns(const ElasticBody &body, const ElasticityModel &model, bool lag);

    /**
     * lambda: the impulses of the step's contacts by projected Gauss-Seidel on @p w, warm
     * started from those of the contacts that persist (same vertex, same obstacle), to
     * @p settings; @p w_lambda then holds W lambda.
     */
    void solve_for_impulses(const ContactCompliance &w, const std::vector<double> &free_velocity,
                            const std::vector<double> &friction, const GaussSeidelSettings &settings,
                            std::optional<ContactCompliance::Product> &w_lambda, StepStatistics &statistics);

    /**
     * u = H v + the targets at @p velocities, 3 rows per contact of the step: the normal
     * velocity plus gap / dt (>= 0 keeps the next position out), the tangential velocities
     * relative to @p obstacle_velocity.
     */
    std::vector<double> contact_velocities(const std::vector<Vector3> &velocities,
                                           const std::vector<Vector3> &obstacle_velocity, double time_step) const;

    /**
     * The check of a lagged W after the correction: the miss (report's aim_error) between
     * the contacts' velocities and Gauss-Seidel's aim, @p free_velocity + W lambda. Past a
     * quarter of the tolerance in the step, Gauss-Seidel again from where the correction
     * left the contacts, and another correcting solve; twice with @p w (to @p gauss_seidel),
     * then with W renewed (@p compliance(true), which drops the kept columns). @p product
     * holds W lambda from Gauss-Seidel, and keeps it. Counts the rounds toward the next
     * renewal.
     */
    void aim_again(const ElasticBody &body, ElasticityModel &model,
                   const std::function<ContactCompliance(bool)> &compliance, ContactCompliance &w,
                   std::optional<ContactCompliance::Product> &product, std::vector<double> free_velocity,
                   const std::vector<double> &friction, const GaussSeidelSettings &gauss_seidel,
                   const std::vector<Vector3> &obstacle_velocity, double time_step,
                   std::vector<Vector3> &velocities, StepStatistics &statistics);

    /** v += A~^-1 H^T (@p impulses, 3 per contact of the step): one solve with the model. */
    void apply_impulses(const ElasticBody &body, ElasticityModel &model, const std::vector<double> &impulses,
                        std::vector<Vector3> &velocities, StepStatistics &statistics) const;

    /** The impulse of contact @p j of the step, lambda in world coordinates. */
    Vector3 impulse_of(std::size_t j) const;

    /** forces, gaps and the report's totals from lambda and the corrected @p velocities. */
    void record_forces_and_gaps(const std::vector<Vector3> &positions, const std::vector<Vector3> &velocities,
                                const std::vector<Vector3> &obstacle_velocity, double time, double time_step);

    /**
     * The gaps after the step at @p velocities of every contact found, the largest
     * penetration, and the run's totals of work and dissipation from the step's report.
     */
    void record_gaps_and_totals(const std::vector<Vector3> &positions, const std::vector<Vector3> &velocities,
                                double time, double time_step);

    /** surface_vertices(), recomputed when the number of cut elements changes. */
    const std::vector<unsigned int> &current_surface(const ElasticBody &body);

    /**
     * Points inside surface triangles near the instruments' tips (spheres, capsules) or
     * the sharp edges of boxes and triangle surfaces (Obstacle::sharp_edges()), whose
     * vertices are not in @p found already: appended to @p found.
     */
    void detect_tips(const ElasticBody &body, const std::vector<Vector3> &positions,
                     const std::vector<Vector3> &velocities, double time, double time_step,
                     std::vector<Contact> &found) const;

    std::vector<Obstacle>     obstacle_list;
    ContactSettings           contact_settings;
    std::vector<unsigned int> surface;
    std::vector<std::array<unsigned int, 3>> triangles;
    unsigned int              surface_of_cut_count = static_cast<unsigned int>(-1);

    std::vector<Contact>      step_contacts, previous_contacts;
    /**
     * The columns of L^-1 of the last step's contact vertices, and their block of A^-1: a
     * cache of the factor, which save() drops.
     */
    mutable cholesky::KeptInverseColumns kept_columns;
    /**
     * Whether the next step renews W (the rounds of the lagged one cost about a renewal),
     * and Gauss-Seidel's rounds after a lagged W's miss since W was renewed: save() renews
     * W as a resumed run does, and counts from zero.
     */
    mutable bool              renew_compliance     = false;
    mutable unsigned int      rounds_since_renewal = 0;
    /** The rounds (a warm Gauss-Seidel and a solve each) that cost about a renewal of W. */
    static constexpr unsigned int rounds_worth_a_renewal = 6;
    /** The impulses of the last step's contacts (3 per contact), the next one's warm start. */
    std::vector<double>       lambda;
    ContactStepReport         report;
    double                    total_work = 0, total_dissipation = 0;
    std::vector<Vector3>      forces;
    std::vector<double>       gaps;

    PenaltySprings            penalty;
  };
} // namespace warpchol::fem
