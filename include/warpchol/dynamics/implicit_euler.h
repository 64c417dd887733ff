#pragma once

#include <warpchol/contact/contact_constraints.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/small_dense.h>
#include <warpchol/fem/system_matrix.h>
#include <warpchol/models/elasticity_model.h>
#include <warpchol/surgery/instrument_path.h>
#include <warpchol/surgery/surgery.h>

#include <tbb/task_arena.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

/**
 * @file
 * Implicit Euler time stepping in velocity form, with the external loads of the scenes.
 */
namespace warpchol::fem
{
  /**
   * A pulling tool, as a surgical instrument grabs tissue: every vertex of a region is
   * tied by a spring of stiffness @p stiffness (N/m) to a target point that starts at the
   * vertex's rest position and moves with @p velocity until time @p duration, then stays;
   * or, with a @p path (a recorded instrument's position), moves as the path does from
   * its position at time 0.
   */
  struct PullingTool
  {
    std::vector<unsigned int> vertices;
    double                    stiffness = 0;
    Vector3                   velocity  = Vector3::Zero();
    double                    duration  = 0;
    InstrumentPath            path;

    /** How far the targets have moved at time @p time. */
    Vector3 target_offset(double time) const;
  };

  /** External loads. */
  struct Loads
  {
    /** Gravitational acceleration (m/s^2), applied as m_i g on every vertex. */
    Vector3 gravity = Vector3::Zero();
    /** A constant force per vertex (N); empty for none. */
    std::vector<Vector3> vertex_forces;
    /** The tool; no vertex for none. */
    PullingTool tool;

    /** Whether a load that does not vanish at rest (gravity, constant forces) acts. */
    bool has_static_load() const;
  };

  /**
   * The velocities of a rigid motion of @p body at rest: v_i = @p linear +
   * @p angular x (X_i - c), c the rest centre of mass (lumped masses), @p angular in rad/s.
   */
  std::vector<Vector3> rigid_body_velocities(const ElasticBody &body, const Vector3 &linear,
                                             const Vector3 &angular);
  /**
   * The 6 rigid-body modes of @p body over its unknowns (free dofs): the translations along
   * x, y, z and the rotations about them through the rest centre of mass. The near null
   * space of the stiffness matrix, which algebraic multigrid needs for elasticity.
   */
  std::vector<std::vector<double>> rigid_body_modes(const ElasticBody &body);

  /**
   * One implicit Euler step in velocity form (DESIGN.md eq. 1):
   *   (M + dt B + dt^2 K) v(t+dt) = M v(t) + dt (f_ext + f_el(x(t)))
   *   x(t+dt) = x(t) + dt v(t+dt)
   * where the model supplies the matrix (rotated as it sees fit), its factor and the
   * elastic forces. The tool's springs are implicit: they add dt^2 k to the diagonal of A
   * (the same in every rotated frame) and dt k (target - x) to the right-hand side. Fixed
   * vertices stay at rest.
   */
  class ImplicitEuler
  {
  public:
    /**
     * The coefficients of A for time step @p time_step, Rayleigh damping (alpha M + beta K)
     * and the springs of @p loads' tool.
     */
    static SystemCoefficients coefficients(const ElasticBody &body, double time_step,
                                           double rayleigh_mass, double rayleigh_stiffness,
                                           const Loads &loads);

    /**
     * Start at rest in the rest configuration at time 0; @p surgery changes @p body (cuts,
     * material) and the boundary conditions (grasps) as the steps go: before each step
     * what happens in it is applied to the body and told to the model.
     */
    ImplicitEuler(ElasticBody &body, ElasticityModel &model, const Loads &loads, double time_step,
                  Surgery surgery = Surgery());

    /**
     * Start from @p velocities (one per vertex) instead of rest; the fixed vertices keep
     * zero. Only before the first step: it sets the initial energy.
     */
    void set_initial_velocities(const std::vector<Vector3> &velocities);

    /**
     * Start from the deformed @p positions (one per vertex) instead of rest, for instance to
     * release a body stretched by another run; the fixed vertices keep their rest
     * positions. Only before the first step: it sets the initial energy.
     */
    void set_initial_positions(const std::vector<Vector3> &positions);

    /**
     * Advance by one time step, on as many threads as the model allows it
     * (ElasticityModel::step_threads()). Throws MatrixError "step N: ..." if the
     * factorization fails or a velocity is not finite, or so large that its square
     * overflows (the simulation diverged).
     */
    void advance(StepStatistics &statistics);

    const std::vector<Vector3> &positions() const;
    const std::vector<Vector3> &velocities() const;
    /** Displacements x - X per vertex. */
    std::vector<Vector3> displacements() const;
    double               time() const;
    unsigned int         step_number() const;

    /**
     * @name Energy accounting
     *
     * The total energy is kinetic + elastic + the potential of the constant loads + the
     * energy of the tool's springs. The only external power is that of the tool's moving
     * targets; a dissipative step (implicit Euler is one: it damps) then keeps
     *   total_energy() <= initial_energy() + external_work(),
     * exactly for the linear model (quadratic energy, fully implicit forces) and up to the
     * linearization of the rotations for the others. A model that gains energy breaks it.
     */
    /** @{ */
    double kinetic_energy() const;
    /** Elastic energy of the current positions, with fresh rotations where the model uses them. */
    double elastic_energy() const;
    /**
     * The elastic energy at the start of the last step (that of the positions one step
     * back), which the model's element pass computed anyway: free where elastic_energy()
     * costs a pass over the elements. elastic_energy() before the first step.
     */
    double elastic_energy_at_step_start() const;
    /**
     * Potential energy of the constant loads (gravity, region forces) relative to rest:
     * -sum_i f_i . (x_i - X_i); minus it is the work they have done.
     */
    double potential_energy() const;
    /**
     * Energy of the tool's springs and of the grasp's: sum over their vertices of
     * 1/2 k |target - x_i|^2.
     */
    double tool_energy() const;
    /** kinetic + elastic + potential + tool energy. */
    double total_energy() const;
    /** The total energy at time 0 (the kinetic energy of the initial velocities). */
    double initial_energy() const;
    /**
     * Work done on the body so far by the tool's moving targets: per step,
     * 1/2 k (|target(t+dt) - x(t)|^2 - |target(t) - x(t)|^2) per tool vertex, the springs'
     * energy gained by moving the targets alone. It is what implicit Euler's energy
     * inequality needs: the step with the new targets dissipates.
     */
    double external_work() const;
    /**
     * The energy the changes of the body (cuts, grasps, material changes) put in or took
     * out so far, each at its step (Surgery::change_energy()): with it the inequality reads
     *   total_energy() <= initial_energy() + external_work() + change_energy().
     */
    double change_energy() const;
    /**
     * Work done on the body so far by the tool's springs: per step, the force
     * k (target(t+dt) - x(t+dt)) the implicit step applied, times x(t+dt) - x(t), summed
     * over the grabbed vertices. Unlike external_work() it leaves out what the springs
     * themselves hold and dissipate: the body's own balance,
     *   kinetic + elastic + potential <= their initial sum + tool_work_on_body(),
     * holds by the same argument, and is much tighter with stiff springs.
     */
    double tool_work_on_body() const;
    /** @} */

    /**
     * Work done on the body so far by the contact impulses (ContactConstraints): what
     * moving obstacles did, less what friction dissipated; 0 without contact.
     */
    double contact_work() const;

    /**
     * Let the body touch @p contact's obstacles from the next step on (only before the
     * first step): after each step's free solve, ContactConstraints::correct(). Throws
     * InputError if an obstacle is inside the body at the start.
     */
    void set_contact(ContactConstraints contact);
    /** The contact step, or null without obstacles. */
    const ContactConstraints *contact() const;

    /** The cuts, grasps and material changes of the run, and what they did so far. */
    const Surgery &surgery() const;
    /** Replace the run's cuts, grasps and material changes; only before the first step. */
    void set_surgery(Surgery surgery);

    /**
     * Write the state of the run to a checkpoint: time, step, positions, velocities (and
     * those of the step before, CG's extrapolated guess), the energy accounts; then the
     * model's (ElasticityModel::save_state()).
     */
    void save_state(BinaryWriter &writer) const;
    /**
     * Read what save_state() wrote into an integrator built for the same scene: the next
     * steps are then those of the run that wrote it, to the bit.
     */
    void load_state(BinaryReader &reader);

  private:
    /**
     * Throw InputError unless the initial @p what ("velocities", "positions") of @p size
     * vertices can still be set: before the first step, one per vertex.
     */
    void check_initial_field(const std::string &what, std::size_t size) const;

    /** m_i g + the constant forces of vertex @p i. */
    Vector3 constant_force(unsigned int i) const;

    /** The step itself: advance() runs it on the threads the model allows. */
    void advance_step(StepStatistics &statistics);
    /**
     * Penalty contact: the springs tied and untied at the step's start joined to
     * @p change (a vertex the surgery's change lists keeps its springs' diagonal on top of
     * the tool's and the grasps').
     */
    void add_penalty_springs(SystemChange &change, StepStatistics &statistics);
    /**
     * Penalty contact, after the step's solve gave @p new_velocities: what the step's
     * acceleration carried in without a spring ties one, and the step is solved again.
     */
    void solve_again_with_entering_springs(std::vector<Vector3> &new_velocities, double new_time,
                                           StepStatistics &statistics);
    /** @p springs joined to @p change (its vertices' springs' diagonal on top of what it lists). */
    void join_penalty_change(const PenaltySprings::Change &springs, SystemChange &change) const;
    /** Penalty contact: rounds of springs tied after a solve, and the step solved again, at most. */
    static constexpr unsigned int max_penalty_rounds = 3;
    /** Whether the contacts push back by penalty springs. */
    bool penalty_contact() const;

    /**
     * The step's right-hand side M v + dt (f_ext + f_el(x) + k (target(@p new_time) - x)).
     * Rayleigh damping adds nothing here: in velocity form it lies in A alone.
     */
    std::vector<Vector3> right_hand_side(double new_time, StepStatistics &statistics) const;

    /**
     * The initial guess of an iterative solve: the velocities extrapolated linearly from
     * the last two steps (the last ones in the first step); empty for a direct solve.
     */
    std::vector<Vector3> initial_guess(StepStatistics &statistics) const;

    ElasticBody         &body;
    ElasticityModel     &model;
    const Loads          loads;
    Surgery              operations;
    /** dt^2 k of the tool's springs per vertex (empty without a tool). */
    std::vector<double>  tool_diagonal;
    const double         time_step;
    double               current_time = 0;
    unsigned int         steps_done   = 0;
    std::vector<Vector3> x;
    std::vector<Vector3> v;
    /** The velocities of the step before (empty before the first step). */
    std::vector<Vector3> previous_v;
    /** m_i g + constant forces: what does not change from step to step. */
    std::vector<Vector3> constant_forces;
    double               start_energy = 0;
    double               tool_work    = 0;
    double               tool_work_on_body_sum = 0;
    /** elastic_energy() costs a pass over the elements: kept for the step it was computed at. */
    mutable double       cached_elastic_energy = 0;
    mutable unsigned int cached_elastic_step   = static_cast<unsigned int>(-1);
    /** The obstacles and the contact step (none without obstacles). */
    std::optional<ContactConstraints> contact_constraints;
    /** The threads of the steps while the model limits them (shared: the integrator is copied). */
    std::shared_ptr<tbb::task_arena> step_arena;
  };
} // namespace warpchol::fem
