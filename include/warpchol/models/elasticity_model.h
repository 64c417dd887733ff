#pragma once

#include <warpchol/backends/linear_solver.h>
#include <warpchol/base/named_values.h>
#include <warpchol/base/stage_times.h>
#include <warpchol/base/types.h>
#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/small_dense.h>
#include <warpchol/fem/system_matrix.h>
#include <warpchol/models/step_strategy.h>

#include <deal.II/lac/vector.h>

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

/**
 * @file
 * The interface shared by the four elasticity models (linear, corotational, stiffness
 * warping, warp-canceling corotation): what differs between them is how the matrix of the
 * implicit Euler step follows the rotation of the elements, and which forces they use.
 */
namespace warpchol::fem
{
  /**
   * The stages of a time step, in the order a step runs them, as StepStatistics::stages
   * names them. A step runs only those its scene needs: no rotations for the linear model,
   * no estimate for WCC at threshold 0 or inf, no factorization when no element changed, no
   * tool springs without a tool, no CG for a direct solve.
   */
  namespace stage
  {
    /** The fused element pass with rotations: element (and nodal) rotations, corotated forces, energy. */
    constexpr const char *rotations = "rotations";
    /** The element pass of the linear model: forces -K_e (x_e - X_e), no rotation. */
    constexpr const char *elastic_forces = "elastic forces";
    /** WCC's error estimate per element. */
    constexpr const char *error_estimate = "error estimate";
    /** (Re-)assembly of the element contributions to A. */
    constexpr const char *assembly = "assembly";
    /** The automatic strategy's choice of a refresh: the flops each would take. */
    constexpr const char *refresh_choice = "refresh choice";
    /** Full or partial numeric factorization of A. */
    constexpr const char *factorization = "factorization";
    /** The tool's spring forces k (target - x), added to the right-hand side. */
    constexpr const char *tool_springs = "tool springs";
    /** M v + dt (gravity, constant, elastic and tool forces). */
    constexpr const char *right_hand_side = "right-hand side";
    /** The velocities extrapolated from the last two steps, as CG's initial guess. */
    constexpr const char *initial_guess = "initial guess";
    /** The triangular solves with the factor (directly, or as CG's preconditioner). */
    constexpr const char *solve = "solve";
    /** Preconditioned CG without its triangular solves: products and vector operations. */
    constexpr const char *cg_iterations = "CG iterations";
    /** WCC with a target error: the step's velocity error against exact corotation. */
    constexpr const char *velocity_error = "velocity error";
    /**
     * A change of the system between steps (a cut, a grasp, a material change): the
     * re-assembly of the columns it touches and their loading as pending changes.
     */
    constexpr const char *change = "change";
    /** Strategy = background: copying the rotations to a refresh and waiting for one to finish. */
    constexpr const char *background_refresh = "background refresh";
    /** x += dt v, with the check that the velocities are finite. */
    constexpr const char *position_update = "position update";
  } // namespace stage

  /** What one step of a model did and what it cost (wall-clock seconds). */
  /**
   * What a step of Strategy = auto or background chose (StepStatistics::choice), as Eigen
   * reports an outcome: a value, named only where it is shown (to_string(): the log, the
   * summary).
   */
  enum class StepChoice
  {
    /** No choice made: a strategy that does not choose ("" in the log). */
    not_chosen,
    /** Every element re-rotated, A factored in full, a direct solve. */
    exact,
    /**
     * auto's fall-back (ExactFallback): the exact path's step (the corotational model's,
     * in the elements' frames), where its own steps had cost more.
     */
    fallback,
    /** A step that iterates after refreshing its factor: all of it, below the top, nothing. */
    refresh_all,
    refresh_below_top,
    refresh_none,
    /** A step that took a refresh made beside the steps. */
    background
  };

  /** The names of the choices (base/named_values.h), as the log and the summary show them. */
  inline constexpr NameTable<StepChoice, 7> step_choice_names{{{StepChoice::not_chosen, ""},
                                                               {StepChoice::exact, "exact"},
                                                               {StepChoice::fallback, "fallback"},
                                                               {StepChoice::refresh_all, "all"},
                                                               {StepChoice::refresh_below_top, "below_top"},
                                                               {StepChoice::refresh_none, "none"},
                                                               {StepChoice::background, "background"}}};

  /** "", "exact", "fallback", "all", "below_top", "none", "background". */
  std::string to_string(StepChoice choice);

  /** The choice of a step that iterates after @p refresh. */
  StepChoice iterating_choice(cholesky::Refresh refresh);

  struct StepStatistics
  {
    /** Elements whose contribution to A was recomputed. */
    Index elements_rerotated = 0;
    /** Whether the factor changed (a full or partial factorization ran). */
    bool refactorized = false;
    /** Columns of L recomputed, and all columns. */
    Index columns_recomputed = 0;
    Index n_columns          = 0;
    /** Flops of the (partial) factorization, and of a full one. */
    double flops_recomputed = 0;
    double flops_full       = 0;

    /** The stages the step ran (names in fem::stage), with their seconds. */
    StageTimes stages;

    /**
     * The seconds of the stages under the names of the log's columns. The element pass
     * counts as rotations with or without them (the linear model's elastic forces).
     */
    double t_rotations() const;
    double t_error_estimate() const;
    double t_assembly() const;
    double t_factor() const;
    double t_solve() const;
    double t_iterations() const;
    /**
     * What the step spent keeping its factor up to date and solving, the element pass
     * excluded: estimate, assembly, refresh choice, factorization, background refresh,
     * solve and CG iterations (what the automatic strategy weighs).
     */
    double strategy_seconds() const;

    /**
     * How the factor was brought up to date in the step, "" if it was not touched:
     * - "full": A factored anew in full (ElasticityModel::factorize(): exact corotation's
     *   steps, WCC's where it factors in full; every factorization by a peer);
     * - "all", "below_top", "none": refactorize() with that cholesky::Refresh (WCC's
     *   strategies: every column that depends on a change, those below the top, none);
     * - "background": the factor a background refresh finished was taken in (Strategy =
     *   background, WarpCancelingModel).
     * The summary counts the steps by this word (RunTotals::refreshes), the log writes it.
     */
    std::string refresh;
    /**
     * The solver's statistics after the step's last factorization (default ones if it
     * factored nothing or a peer factored): how it took its changes (method: update,
     * partial or full) and what it weighed (update_rank, the predicted seconds; negative if
     * it weighed no update). Copied whole, so that every reported field
     * (cholesky::statistics_fields(), which the log's columns read) comes with it. The
     * seconds spent are t_factor().
     */
    cholesky::SparseCholesky::Statistics factorization;
    /** Iterations of preconditioned CG (0 for a direct solve). */
    unsigned int cg_iterations = 0;
    /** The paths the element rotations of the step's element pass took (none without rotations). */
    RotationPaths rotation_paths;
    /**
     * How far the step's velocities are from those of exact corotation, max_i |v_i -
     * v_i*| / max_i |v_i| (measured by WCC with a target error); negative if not measured.
     */
    double velocity_error = -1;
    /**
     * The step's changes of the system (ElasticityModel::apply_change()): elements cut,
     * vertices grasped or released, elements whose material changed; the columns of A they
     * changed and the flops a refactorization of those columns alone costs.
     */
    unsigned int elements_cut      = 0;
    unsigned int vertices_grasped  = 0;
    unsigned int vertices_released = 0;
    unsigned int elements_changed  = 0;
    Index        change_columns    = 0;
    double       change_flops      = 0;

    /** The WCC re-rotation threshold of the step (negative for the other models). */
    double rerotation_threshold = -1;
    /**
     * Steps between the rotations the factor was made with and this step (Strategy =
     * background; negative for the others).
     */
    int factor_lag = -1;
    /**
     * Strategy = auto or background: what the step chose, and the seconds the cost model
     * predicted for it (negative if none).
     */
    StepChoice  choice = StepChoice::not_chosen;
    double      predicted_seconds = -1;

    /** Add the stage times of @p step to these: totals over steps. */
    void add_phase_times(const StepStatistics &step);
  };

  /**
   * What changed in the system between two steps, besides the rotations: the elements whose
   * contribution changed (cut, or their material scaled; ElasticBody holds the new state)
   * and the vertices whose diagonal did (a spring tied or untied, an orphaned vertex's
   * mass), with their new diagonal values.
   */
  struct SystemChange
  {
    std::vector<unsigned int> elements;
    std::vector<unsigned int> vertices;
    /** The value added to each of @p vertices' 3 diagonal entries from now on. */
    std::vector<double>       vertex_diagonal;
    /** Whether elements were cut (the topology changed: a peer that analyzes anew does). */
    bool                      topology = false;

    bool empty() const;
  };

  /** Per element: how up to date its contribution to A is, its rotations' age (for output). */
  struct ElementRerotationRecord
  {
    /** 1 if the element was re-rotated (its contribution recomputed) in the last step. */
    std::vector<unsigned char> rerotated;
    /** Steps since the element was last re-rotated (0: in the last step). */
    std::vector<unsigned int> steps_since_rerotation;
    /** The relative error estimate of the last step; empty if the model estimates none. */
    std::vector<double> error_estimate;
  };

  /**
   * An elasticity model: owns the system matrix A = c_M M~ + c_K K~ (+ tool springs) over the
   * free dofs and its Cholesky factor, and solves the implicit Euler step in the form
   *   R A R^T v = rhs,  that is  A y = R^T rhs, v = R y,
   * with R the block-diagonal nodal rotations (the identity for the linear and corotational
   * models). A step is prepare_step() (rotations, matrix updates, factorization), then
   * add_elastic_forces() for the right-hand side, then solve().
   */
  class ElasticityModel
  {
  public:
    /**
     * The model sets its system up and factors it. @p coefficients are those of the time
     * step, @p solver_settings the ordering and method of warpchol's factorization. With a
     * @p peer (Solver/Backend) the peer factors and solves A instead: every factorization
     * in full, solve() the peer's, directly or by its own iterations; warpchol's solver then
     * only analyzes A (the flops of a full factorization, which the statistics count) and
     * holds no numeric factor. A step that needs warpchol's factor (an iterating strategy,
     * a target error) is refused by the parameters before this.
     */
    ElasticityModel(const ElasticBody &body, const SystemCoefficients &coefficients,
                    const cholesky::SparseCholesky::Settings &solver_settings,
                    std::unique_ptr<backends::LinearSolver> peer = nullptr);
    virtual ~ElasticityModel() = default;

    /** "linear", "corotational", ... */
    virtual std::string name() const = 0;

    /**
     * What the model reports of its re-rotation threshold and step strategy, for the run's
     * summary: the app asks the model, never its type. Empty (has_strategy false) but for
     * WCC.
     */
    struct StrategyReport
    {
      bool         has_strategy     = false;
      double       rerotation_threshold = 0;
      /** 0 when the threshold stays fixed. */
      double       target_error = 0;
      /** Why and from which step a target error gave up (empty while it steers). */
      std::string  target_note;
      StepStrategy strategy;
      /** auto with a background refresh: the steps with the refreshes beside them, and in them. */
      unsigned int steps_refreshing_beside = 0;
      unsigned int steps_refreshing_in     = 0;
      /** auto: the steps it ran exact where its own had cost more, and how many times it fell back. */
      unsigned int exact_fallback_steps = 0;
      unsigned int fallbacks            = 0;
      /** Of those, the stretches that ended early: their exact steps cost as much as the own ones (a slow spell). */
      unsigned int fallbacks_ended      = 0;
    };
    virtual StrategyReport strategy_report() const;

    /**
     * Bring A and its factor up to date with the configuration at the start of a step.
     * Throws MatrixError naming the column and vertex if the factorization fails.
     */
    virtual void prepare_step(const std::vector<Vector3> &positions,
                              const std::vector<Vector3> &velocities,
                              StepStatistics             &statistics) = 0;

    /**
     * Take in @p change before the next prepare_step(): re-assemble the columns of A it
     * touches (with the frames the model's contributions are made in) and load them into
     * the factor as pending changes, which the step's refactorization takes with its own:
     * the partial refactorization recomputes the columns that depend on them, a direct
     * solve never runs on a factor that misses them, a strategy that iterates weighs them
     * as any other. A peer that replaces the factor factors in full anyway (and, after a
     * cut, analyzes anew, as SOFA's solvers do on a topological change).
     */
    virtual void apply_change(const SystemChange &change, StepStatistics &statistics);

    /**
     * Take in @p change between prepare_step() and the step's solve (penalty springs tied
     * after a first solve): its columns are re-assembled with the step's frames at once,
     * also by a model that assembles A every step, and the next solve takes them (a direct
     * solve refactors them first; CG iterates on the changed A).
     */
    void change_within_step(const SystemChange &change, StepStatistics &statistics);

    /** What is added to each of @p vertex's 3 diagonal entries now (springs; SystemChange::vertex_diagonal). */
    double vertex_diagonal(unsigned int vertex) const;

    /**
     * forces += the elastic forces at @p positions, which were given to the last
     * prepare_step(): exact corotated forces for every model but the linear one, as the
     * fused element pass of prepare_step() computed them.
     */
    virtual void add_elastic_forces(const std::vector<Vector3> &positions,
                                    std::vector<Vector3>       &forces) const;

    /**
     * Solve R A R^T v = @p right_hand_side for the velocities of the free vertices; those
     * of the fixed vertices are set to zero. With an iterating strategy, the system is
     * that of the strategy's target matrix (the exact corotational one, or A), solved by
     * preconditioned CG with the factor of A as the preconditioner; should CG not converge,
     * the factor is refreshed in full and CG runs again. Throws MatrixError if it still
     * does not converge. CG starts from @p velocities as given (the last step's, a good
     * guess), or from zero if it has the wrong size.
     */
    void solve(const std::vector<Vector3> &right_hand_side, std::vector<Vector3> &velocities,
               StepStatistics &statistics);

    /**
     * solve() once more in the same step (a contact's correction, A^-1 H^T lambda): its CG
     * iterations and seconds add to those of the step's solve, which a strategy that
     * weighs its steps (auto's cost model) reads as the step's, instead of replacing them.
     */
    void solve_again(const std::vector<Vector3> &right_hand_side, std::vector<Vector3> &velocities,
                     StepStatistics &statistics);

    /**
     * Whether the next solve() iterates (preconditioned CG, which starts from the velocities
     * it is given) rather than solving directly with the factor: not in a step whose factor
     * is that of the strategy's target matrix (factor_solves_target()).
     */
    bool solves_iteratively() const;

    /**
     * The steps the run takes in all (0, the default: not known). A strategy that makes
     * its factor exact to serve the steps after it (the automatic one) does not do so for
     * steps that cannot repay it.
     */
    void set_run_length(unsigned int steps);

    /** Whether the model uses rotations at all (all but the linear one). */
    virtual bool uses_rotations() const;

    /**
     * The nodal rotations R of solve()'s frame (it solves A y = R^T rhs, v = R y), or null
     * for the identity: a constraint row h on the velocities is the row R^T h on A's
     * unknowns (contact/contact_constraints.h).
     */
    const std::vector<Matrix3> *solve_rotations() const
    {
      return solve_frame;
    }

    /**
     * How many threads the next step's own work may use: 0 for all that deal.II allows;
     * fewer while a thread of the model's works beside the steps (WarpCancelingModel's
     * background refresh), so that it keeps a core to itself instead of slowing every
     * parallel loop of the step. 0 by default.
     */
    virtual unsigned int step_threads() const;

    /**
     * The elastic energy at the positions of the last prepare_step() (the start of the
     * last step), which its element pass computed anyway.
     */
    double elastic_energy_at_last_evaluation() const;

    /** The peer's solver, or null for warpchol's factor. */
    const backends::LinearSolver *linear_solver() const;
    /** Bytes of the factor (warpchol's or the peer's) or of the peer's preconditioner. */
    std::size_t factor_memory_bytes() const;

    const ElementRerotationRecord &rerotation_record() const;
    const SystemMatrix        &system_matrix() const;
    const cholesky::SparseCholesky &solver() const;
    /** Seconds spent in the set-up: assembly, ordering, symbolic and first factorization. */
    double setup_seconds() const;

    /**
     * What one iteration of preconditioned CG moves through memory, in bytes read and
     * written, counted from the sizes of what it reads: the preconditioner's factor read
     * twice (the forward and the backward solve: its values, in the precision the
     * preconditioner keeps them, and its row indices), the product (the assembled A's lower
     * triangle, or the matrix-free corotated product: per element its rotation, inverse
     * rest edges, volume and vertices, the 4 vertices' values; per vertex the span of its
     * elements and its sum written), and CG's own passes over its vectors (ten of n doubles).
     */
    struct IterationBytes
    {
      double preconditioner = 0, product = 0, vectors = 0;
      double total() const;
    };
    IterationBytes cg_iteration_bytes() const;

    /**
     * The rate (bytes per second) at which the CG iterations so far (products, solves,
     * vector operations) moved cg_iteration_bytes(); 0 before any.
     */
    double cg_bytes_per_second() const;

    /**
     * From now on, measure how far each step's velocities are from the exact corotational
     * system's (StepStatistics::velocity_error), as a target error does: what the summary
     * reports as the error against exact corotation when no reference runs beside.
     */
    void measure_velocity_errors();

    /**
     * Write what the model carries from step to step to a checkpoint: A, its element
     * contributions and the factor as it is (if matrix_carries_over()), the update record
     * and what the last solve measured; a derived model adds its own (save_model_state()).
     */
    void save_state(BinaryWriter &writer) const;
    /**
     * Read what save_state() wrote, into a model set up for the same body and parameters:
     * its next steps are then those of the model that wrote it, to the bit. A peer's
     * solver factors the restored A again (the same factor: it factors A in full).
     */
    void load_state(BinaryReader &reader);

  protected:
    /**
     * Whether A and its factor at the end of a step depend on the steps before, not only
     * on the parameters (set-up) or on the next step's positions (which rebuild them in
     * full): only then does a checkpoint hold them. False by default.
     */
    virtual bool matrix_carries_over() const;
    /**
     * CG did not converge with the factor of A as the preconditioner: bring A and its
     * factor closer to the target matrix and return true, or return false when nothing
     * better can be done (then solve() gives up). By default: refactorize what is pending
     * or stale if the factor is not exact.
     */
    virtual bool refresh_after_failed_solve(StepStatistics &statistics);
    /**
     * The CG iterations after which this step's solve counts as failed
     * (refresh_after_failed_solve()): Max CG iterations by default.
     */
    virtual unsigned int cg_iteration_limit() const;
    /**
     * Whether this step's CG also gives up as soon as its convergence forecasts the limit
     * passed (ForecastSolverControl): false by default.
     */
    virtual bool cg_gives_up_on_forecast() const;

    /**
     * The frames A's element contributions are made in now: at rest by default (the linear
     * model, stiffness warping).
     */
    virtual ElementFrames contribution_frames() const;
    /** Whether prepare_step() assembles every element anyway (corotation): false by default. */
    virtual bool assembles_every_step() const;

    /**
     * Whether the factor of A is, this step, the exact factor of the matrix an iterating
     * strategy would iterate on: solve() then solves directly. False by default.
     */
    virtual bool factor_solves_target() const;

    /** What a derived model carries from step to step besides the base's: none by default. */
    virtual void save_model_state(BinaryWriter &writer) const;
    virtual void load_model_state(BinaryReader &reader);

    /**
     * Assemble A at rest (every rotation the identity) and factor it, timing it as the
     * model's set-up: what every model starts from. A is assembled in contribution_frames(),
     * the form the model re-assembles A's columns in later, so that a column re-assembled
     * unchanged keeps its bits (the rest and the warped forms round apart): called from the
     * model's own constructor, once its frames are set.
     */
    void set_up_rest_system();

    /** Full numeric factorization of the current A (analyzed on the first call). */
    void factorize(StepStatistics &statistics);

    /**
     * The corotational model's step: the element rotations at @p positions, A assembled
     * with every vertex of element e in its frame R_e (R_e K_e R_e^T), every element
     * recorded as re-rotated, A factored in full. WCC's fall-back runs it too.
     */
    void corotational_exact_step(const std::vector<Vector3> &positions, StepStatistics &statistics);

    /** Whether the factor (warpchol's or the peer's) is that of the current A. */
    bool factor_is_exact() const;
    /**
     * Partial refactorization after @p changed_columns of A changed, bringing the factor up
     * to date as far as @p refresh says (SparseCholesky::refactorize()).
     */
    void refactorize(const std::vector<Index> &changed_columns, StepStatistics &statistics,
                     cholesky::Refresh refresh = cholesky::Refresh::all);

    /** Run @p factor; a failed pivot becomes a MatrixError naming column and vertex. */
    void checked(const std::function<void()> &factor);

    /** The sizes a step that does not refactorize reports (columns and full flops). */
    void record_no_refactorization(StepStatistics &statistics) const;

    /** Record that @p rerotated (sorted) were re-rotated this step, the others not. */
    void record_rerotations(const std::vector<unsigned int> &rerotated);
    /** Record that all or no element was re-rotated this step. */
    void record_rerotations(bool all);

    /**
     * The fused element pass at @p positions (ElasticBody::evaluate): rotations as the
     * model needs them, corotated forces, energy; timed as the step's stage "rotations",
     * or "elastic forces" without rotations.
     */
    void evaluate_elastic_state(const std::vector<Vector3> &positions,
                                ElasticBody::Rotations rotations, StepStatistics &statistics);

    /** apply_change() and change_within_step(): the latter re-assembles at once, whatever the model. */
    void load_change(const SystemChange &change, bool within_step, StepStatistics &statistics);

    /**
     * The nodal rotations R in which solve() works; null means the identity. Set by the
     * models that warp (stiffness warping, warp-canceling corotation).
     */
    const std::vector<Matrix3> *solve_frame = nullptr;

    const ElasticBody       &body;
    /** A's coefficients; the vertex diagonal changes with apply_change(). */
    SystemCoefficients       coefficients;
    SystemMatrix             system;
    cholesky::SparseCholesky cholesky_solver;
    ElementRerotationRecord      record;
    double                   setup_time = 0;
    /** Rotations, forces and energy at the positions of the last prepare_step(). */
    ElasticBody::State       elastic_state;
    /** How the steps are solved (partial: directly; the others by preconditioned CG). */
    StepStrategy             strategy;
    /** What the last solve() did: its CG iterations and their seconds (solves included). */
    unsigned int             last_cg_iterations = 0;
    double                   last_cg_seconds    = 0;
    unsigned long            total_cg_iterations = 0;
    double                   total_cg_seconds    = 0;
    /** The seconds of the last solve(), direct or by CG, refreshes after a failed CG included. */
    double                   last_solve_seconds = 0;
    /**
     * Whether solve() measures how far its solution is from the exact corotational one
     * (StepStatistics::velocity_error, kept in last_velocity_error): one matrix-free
     * product with the corotational matrix and one solve with the factor, the stage
     * "velocity error".
     */
    bool                     measure_velocity_error = false;
    double                   last_velocity_error    = -1;
    /** How much of the factor the last refactorize() refreshed. */
    cholesky::Refresh        last_refresh = cholesky::Refresh::all;
    /** Whether A changed (apply_change()) since the peer last factored it. */
    bool                     peer_factor_stale = false;
    /**
     * SystemMatrix::n_whole_changes() when cholesky_solver last read A: while it is the
     * same, the columns that re-assembly returned since are all that changed, and the
     * solver reads only those (cholesky::ChangeListing::complete).
     */
    std::uint64_t            whole_changes_read = std::numeric_limits<std::uint64_t>::max();
    /** The peer that replaces cholesky_solver (Solver/Backend); null: warpchol's own. */
    std::unique_ptr<backends::LinearSolver> peer_solver;
    /** set_run_length(): the steps of the run (0: not known). */
    unsigned int             run_length = 0;

  private:
    /**
     * cholesky_solver.refactorize() of A, telling it the listing of @p changed_columns is
     * complete where no whole change of A came between (whole_changes_read).
     */
    void refactorize_solver(const std::vector<Index> &changed_columns, cholesky::Refresh refresh);

    /** solve(), untimed: it calls itself again after a refresh of a failed CG. */
    void solve_in_frame(const std::vector<Vector3> &right_hand_side, std::vector<Vector3> &velocities,
                        StepStatistics &statistics);

    /**
     * y = B^-1 b by preconditioned CG from the initial guess @p y, B the strategy's target
     * matrix in the solve frame, the factor of A the preconditioner. Returns the
     * iterations; throws
     * dealii::SolverControl::NoConvergence if the tolerance is not reached.
     */
    unsigned int solve_by_cg(const std::vector<double> &b, std::vector<double> &y,
                             StepStatistics &statistics);

    /**
     * max_i |y*_i - y_i| / max_i |y_i| per vertex for the solution y of the step's system
     * with right-hand side @p b and y* that of the exact corotational system, y* - y
     * approximated by A^-1 (b - B y) with the factor of A.
     */
    double relative_velocity_error(const std::vector<double> &b, const std::vector<double> &y);

    /** unknowns = R^T field on the free vertices (R: the solve frame, or the identity). */
    void to_solve_frame(const std::vector<Vector3> &field, double *unknowns) const;
    /** field = R unknowns on the free vertices, 0 on the fixed ones. */
    void from_solve_frame(const double *unknowns, std::vector<Vector3> &field) const;

    /** out = B y for the strategy's target matrix B, over the unknowns. */
    void target_times(const dealii::Vector<double> &y, dealii::Vector<double> &out) const;
    /** out = R^T B R y for the exact corotational matrix B, matrix-free. */
    void corotational_times(const dealii::Vector<double> &y, dealii::Vector<double> &out) const;

    /** Work arrays of the matrix-free products (per vertex, per element). */
    mutable std::vector<Vector3> vertex_work, vertex_product, mass_product;
    mutable ElasticBody::ForceWork element_work;

    /** A full factorization of A by the peer's solver, recorded in @p statistics. */
    void factorize_with_peer(StepStatistics &statistics);

    /** Copy what the solver's last (re)factorization did into @p statistics. */
    void record_refactorization(StepStatistics &statistics) const;
  };
} // namespace warpchol::fem
