#pragma once

#include <warpchol/models/background_refresh.h>
#include <warpchol/models/contribution_frames.h>
#include <warpchol/models/elasticity_model.h>
#include <warpchol/models/target_error_controller.h>

#include <array>
#include <optional>
#include <string>
#include <limits>

/**
 * @file
 * Warp-canceling corotation (Hecht, Lee, Shewchuk and O'Brien, ACM TOG 31(5), 2012).
 */
namespace warpchol::fem
{
  /** What WCC's estimate finds for one element (see WarpCancelingModel). */
  struct ElementErrorEstimate
  {
    /** err_e = || (A_e[R, R_e] - A_e[stored]) z ||, an impulse (N s). */
    double error = 0;
    /** The element's share of the impulse scale: || A_e[R, R_e] z || + dt || f_e ||. */
    double impulse = 0;
  };

  /**
   * WCC's estimate for element @p e of @p body, matrix-free: @p velocities per vertex (world
   * frame), @p nodal_velocities = R_v^T v_v with @p nodal_rotations R_v, the element's
   * current rotation @p element_rotation, the frames T_a = S_a^T Q_e its stored contribution
   * was made with, and @p force_norm the norm of its 12 nodal elastic forces. The serial
   * model and each rank of a distributed run (distributed/) call it per element.
   */
  ElementErrorEstimate estimate_element_error(const ElasticBody &body, const SystemCoefficients &coefficients,
                                              unsigned int e, const std::vector<Vector3> &velocities,
                                              const std::vector<Vector3> &nodal_velocities,
                                              const std::vector<Matrix3> &nodal_rotations,
                                              const Matrix3 &element_rotation,
                                              const std::array<Matrix3, 4> &frames, double force_norm);

  /**
   * A_e with the current rotations (S_a = @p nodal_rotations of its vertices, Q_e =
   * @p element_rotation): what element @p e contributes to A once WCC re-rotates it; @p frames
   * receives the T_a = S_a^T Q_e it is made with, which the estimate compares against
   * until the next re-rotation. The serial model and each rank of a distributed run call it.
   */
  ElementMatrix rerotated_contribution(const ElasticBody &body, const SystemCoefficients &coefficients, unsigned int e,
                                     const std::vector<Matrix3> &nodal_rotations, const Matrix3 &element_rotation,
                                     std::array<Matrix3, 4> &frames);

  /**
   * A setting of WCC that another rules out: the parameter file's entry that asks for it
   * (Subsection/Entry) and why.
   */
  struct SettingConflict
  {
    /** Which rule: the threshold a target error starts from, or another. */
    enum class Rule
    {
      threshold_range,
      target_range,
      target_needs_finite_threshold,
      target_needs_wcc_system,
      background_iterates_on_corotational,
      top_needs_supernodes
    };
    Rule        rule;
    std::string subsection;
    std::string entry;
    std::string message;
  };

  /**
   * The rules that tie WCC's settings together, in one place: the model's constructor
   * throws on the first broken one, the parameter file names its entry and line. Empty if
   * @p rerotation_threshold, @p target_error, @p strategy and the solver's @p method agree.
   */
  std::optional<SettingConflict> wcc_setting_conflict(double rerotation_threshold, double target_error,
                                                      const StepStrategy           &strategy,
                                                      cholesky::FactorizationMethod method);

  /**
   * Warp-canceling corotation (WCC). Every element e keeps the nodal rotations S_a of its
   * vertices and its own rotation Q_e from the step it was last *re-rotated* (in the
   * contribution the SystemMatrix keeps for it), and contributes
   *   A_e = c_M diag(S_a^T) M_e diag(S_b) + c_K diag(S_a^T Q_e) K_e diag(Q_e^T S_b)
   * to A. The step solves R A R^T v = rhs with the current nodal rotations R: where an
   * element is up to date (S = R, Q_e = R_e) this is exact corotation; where it is not, the
   * nodal rotations stand in for the missing re-rotation.
   *
   * Which elements to re-rotate. With z = R^T v_e (v_e the element's nodal velocities) the
   * exact and the approximate contributions of e to the left-hand side differ by
   *   err_e = || (A_e[R, R_e] - A_e[stored S, Q]) z ||
   * (rotating by R changes no norm), an impulse (N s). The threshold is dimensionless,
   * relative to the impulse scale of the step
   *   I = mean over elements of ( || A_e[R, R_e] z || + dt || f_e || ),
   * the typical size of an element's terms in the impulse balance A v = M v + dt f: its
   * exact contribution to A v and its elastic impulse (f_e = R_e K_e (R_e^T x_e - X_e)).
   * Element e is re-rotated when err_e > threshold * I. A rigid translation leaves err_e / I at
   * rounding level (1e-16), so any threshold above about 1e-12 treats it as no change. As a
   * loaded body comes to rest, err_e vanishes with the velocities while its elastic
   * impulse keeps I finite: the re-rotations die out. A body at rest and unloaded (I = 0)
   * re-rotates nothing.
   *
   * Threshold 0 re-rotates every element without estimating anything: the step is then exact
   * corotation (assembled and factored in full). An infinite threshold never re-rotates and
   * estimates nothing: the step is then exactly stiffness warping. In between, the re-rotated
   * elements' entries are re-assembled and the factor is refactorized partially, for the
   * dofs of their vertices only; nothing is refactorized in a step with no update.
   *
   * How much of the factor a step recomputes and how it solves is the StepStrategy: the
   * partial refactorization and a direct solve above, or a factor refreshed in part (below
   * the top of the elimination tree, or not at all) as the preconditioner of CG on the
   * exact corotational matrix, chosen per step by a cost model for the automatic one.
   *
   * A target error instead of a fixed threshold. The estimate ranks the elements well,
   * but how much trajectory error a threshold leaves depends on the scene: a body that
   * swings (large rotations, small strains) accumulates its stale rotations coherently
   * and needs a threshold ten times lower than a pulled one for the same error. With a
   * target error t > 0 the model measures after every solve how far the step's
   * velocities are from exact corotation (ElasticityModel::relative_velocity_error, one
   * matrix-free product and one solve), e_k = max_i |v_i - v_i*| / max_i |v_i|, and moves
   * the threshold of the next step so that e_k follows t / 2:
   *   threshold *= clamp((t / 2 / e_k)^0.7, 1/8, 2), at most 100.
   * Measured on four scenes (parameters/README.md), the trajectory error is 1 to 2.5
   * times the mean step error: t / 2 keeps it near t whatever the scene.
   */
  class WarpCancelingModel : public ElasticityModel
  {
  public:
    /** @p rerotation_threshold >= 0, possibly infinite; @p peer as ElasticityModel's. */
    WarpCancelingModel(const ElasticBody &body, const SystemCoefficients &coefficients,
                       const cholesky::SparseCholesky::Settings &solver_settings,
                       double rerotation_threshold, const StepStrategy &step_strategy = StepStrategy(),
                       double target_error = 0, std::unique_ptr<backends::LinearSolver> peer = nullptr);

    std::string name() const override;

    void prepare_step(const std::vector<Vector3> &positions, const std::vector<Vector3> &velocities,
                      StepStatistics &statistics) override;

    /**
     * A refresh in flight beside the steps is taken first (it read the body as it was), then
     * the change is applied as ElasticityModel::apply_change() does.
     */
    void apply_change(const SystemChange &change, StepStatistics &statistics) override;


    /** The threshold the model was given (with a target error: the one it started from). */
    double rerotation_threshold() const;
    /** The threshold of the step to come (the given one, unless a target error adapts it). */
    double current_rerotation_threshold() const;
    /** The target error; 0 when the threshold stays fixed. */
    double target_error() const;

    const StepStrategy &step_strategy() const;

    /**
     * Empty while the target error steers the threshold; once it gave up (no threshold
     * holds the target with few re-rotations: see prepare_step()), why and from which step.
     */
    const std::string &target_note() const;

    /**
     * One thread less than the solver was given while a background refresh is in flight
     * (it has a core to itself), 0 (all of them) otherwise.
     */
    unsigned int step_threads() const override;

    /** auto with a background refresh: where it placed the refreshes (steps run each way). */
    const RefreshPlacement &refresh_placement() const;

    /** auto's fall-back to exact steps where its own cost more (ExactFallback). */
    const ExactFallback &exact_fallback() const;

    StrategyReport strategy_report() const override;

  protected:
    /**
     * At a threshold strictly between 0 and inf, A is re-assembled in part and its factor
     * refreshed in part; with Strategy = background, both come from the refreshes.
     */
    bool matrix_carries_over() const override;
    /**
     * After CG failed with an exact factor of A, or with any factor where auto bounds CG
     * (cg_iteration_limit()): update every element to the current rotations (A is then
     * the exact corotational matrix) and factor it in full. Otherwise refresh what is stale.
     */
    bool refresh_after_failed_solve(StepStatistics &statistics) override;
    /**
     * auto iterating on the corotational matrix: at most the iterations an exact step costs
     * (StepCostModel::affordable_iterations()), then an exact step; Max CG iterations otherwise.
     */
    unsigned int cg_iteration_limit() const override;
    /** Where auto bounds CG by an exact step: a solve that will not make it is cut short. */
    bool cg_gives_up_on_forecast() const override;
    /** After a step that re-rotated every element: A is the exact corotational matrix. */
    bool factor_solves_target() const override;
    /** Every element in the frames it was last re-rotated with. */
    ElementFrames contribution_frames() const override;
    /** The stored frames, the adapted threshold and what the strategy measured. */
    void save_model_state(BinaryWriter &writer) const override;
    void load_model_state(BinaryReader &reader) override;

  private:
    /**
     * auto iterating on the corotational matrix: where its steps may be exact, fall back to
     * the exact path's, refresh beside the steps and bound CG by an exact step.
     */
    bool automatic_on_corotational() const;
    /** Whether auto bounds this step's CG by the iterations an exact step costs (once known). */
    bool cg_bounded_by_exact_step() const;

    /** The elements whose error estimate exceeds the threshold, in increasing order. */
    std::vector<unsigned int> elements_to_rerotate(const std::vector<Vector3> &velocities);

    /**
     * Re-rotate element @p e: its frames become S_a^T Q_e with this step's solve rotations
     * S_a of its vertices and its rotation Q_e = R_e (ContributionFrames), which its
     * contribution to A is made with until its next re-rotation.
     */
    void rerotate_frames(unsigned int e);

    const double threshold;
    /** The threshold of the next step: the given one, or adapted to the target error. */
    TargetErrorController target_control;

    /** What each element's contribution to A was made with, and the rotations A is solved with. */
    ContributionFrames warp_frames;

    /** The refresh of this step's factor, as the strategy says (timed if it weighs them). */
    cholesky::Refresh choose_refresh(const std::vector<Index> &changed_columns,
                                     StepStatistics           &statistics);

    /** Work array of the estimate: R_v^T v_v per vertex. */
    std::vector<Vector3> nodal_velocities;

    /**
     * Bring A and its factor up to date as the strategy says, after the element pass:
     * what prepare_step() times as the step's own work.
     */
    void prepare_factor(const std::vector<Vector3> &velocities, StepStatistics &statistics);

    /** Leave the target error: iterate on the corotational matrix (preconditioned) from now on. */
    void give_up_target();

    /** Update every element to the current rotations, assemble A and factor it in full. */
    void exact_step(StepStatistics &statistics);

    /**
     * The exact path's step, where auto's own steps cost more (ExactFallback): the element
     * rotations at @p positions, A assembled in the elements' frames (the corotational
     * model's matrix: no nodal rotation, no frame per vertex) and factored in full, solved
     * directly in the world frame. Nothing else: no error estimate, no refresh choice,
     * nothing for the cost model. It is also WCC's exact matrix, of reference the nodal
     * rotations of this step (ContributionFrames): the next step of auto's own goes on
     * from its factor.
     */
    void corotational_step(const std::vector<Vector3> &positions, StepStatistics &statistics);

    /**
     * Take the background refresh in flight if it is due (Strategy = background: after
     * Background lag steps, or as soon as it is done with lag 0; auto: as soon as it is
     * done) and start the next one if none is in flight. Returns whether it took one.
     */
    bool take_background_refresh(StepStatistics &statistics);

    /**
     * Whether the factor is refreshed beside the steps: always with Strategy = background,
     * with auto where RefreshPlacement measured that it pays.
     */
    bool refreshes_beside_the_steps() const;

    /** Strategy = background, or auto with two threads or more: the refresh beside the steps. */
    std::unique_ptr<BackgroundRefresh> background;
    /** The threads the solver was given: the steps' when no refresh runs beside them. */
    const unsigned int given_threads;
    /** The threads of the step being prepared (step_threads(), or all). */
    unsigned int step_thread_count;
    /** auto with a background refresh: in the steps or beside them, as measured. */
    RefreshPlacement placement;
    ExactFallback    fallback;
    /** The whole of the last prepare_step() (element pass included), in seconds. */
    double last_step_prepare_seconds = 0;
    /** Where the steps stand against the factor, and what the last one measured: checkpointed. */
    struct StepHistory
    {
      /** The steps prepared so far (the step being prepared is step_count). */
      unsigned int step_count = 0;
      /** The step whose rotations A and its factor were made with (0: at rest). */
      unsigned int factor_step = 0;
      /** What the last step measured for the cost model: its own seconds, whether it was exact, its staleness. */
      double       last_prepare_seconds = 0;
      bool         last_step_exact      = false;
      unsigned int last_staleness       = 0;
      /** The staleness the factor had reached when the last exact step came. */
      unsigned int cycle_length = 0;
      /** Whether the last step took in a change of the system (a cut, a grasp). */
      bool         last_step_changed = false;
      /** Whether the last step was the exact path's (corotational_step()): not auto's own to measure. */
      bool         last_step_fell_back = false;
      /**
       * Whether this step's CG failed (past cg_iteration_limit()) and the factor was refreshed
       * in the solve: its seconds are those of no step the cost model foresees.
       */
      bool         solve_failed = false;
      /** delayed_top: steps since the top was last refreshed. */
      unsigned int steps_since_top_refresh = 0;

      template <typename Archive>
      void serialize(Archive &archive)
      {
        archive &step_count &factor_step &last_prepare_seconds &last_step_exact &last_staleness &cycle_length
          &last_step_changed &last_step_fell_back &solve_failed &steps_since_top_refresh;
      }
    };
    StepHistory history;

    /** Whether a change of the system came before this step (apply_change()). */
    bool change_pending = false;
    /** Whether A is the exact corotational matrix of this step's rotations, factored. */
    bool exact_this_step = false;

    /** automatic: what each refresh will cost. */
    StepCostModel    cost_model;
  };
} // namespace warpchol::fem
