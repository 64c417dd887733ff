#pragma once

#include <warpchol/base/named_values.h>
#include <warpchol/cholesky/sparse_cholesky.h>

#include <string>

/**
 * @file
 * How a step of warp-canceling corotation keeps its factor up to date and solves: past the
 * ceiling of partial refactorization (DESIGN.md, "Past the ceiling").
 */
namespace warpchol::fem
{
  /**
   * The strategies of a WCC step. Every step re-assembles the elements whose error estimate
   * exceeds the threshold; what differs is how much of the factor is recomputed and how
   * the step's system is solved.
   */
  struct StepStrategy
  {
    enum class Kind
    {
      /**
       * Partial refactorization of every column that depends on a change, then a direct
       * solve: the step solves the WCC system exactly (its error is WCC's matrix error).
       */
      partial,
      /**
       * Every step only the dirty supernodes below the top of the elimination tree (the
       * solver's top_flops_fraction); the top, which holds most flops, every
       * refresh_interval steps or when the last solve needed more than refresh_iterations
       * iterations. The factor is then the exact factor of no matrix: preconditioned CG.
       */
      delayed_top,
      /**
       * Partial refactorization as for partial, the factor then the preconditioner of CG on
       * the target matrix (SOFA's warp preconditioner with a factor kept fresh where it
       * matters): WCC's matrix error becomes iterations instead of trajectory error.
       */
      preconditioned,
      /**
       * Per step, the cheapest of refreshing all, below the top or nothing, by a cost model
       * calibrated from the measured flop rate and iteration times; preconditioned CG.
       */
      automatic,
      /**
       * Refresh on a thread of its own (BackgroundRefresh): the matrix with every element
       * updated at one step's rotations is assembled and factored beside the steps, which
       * meanwhile solve by CG preconditioned with the last factor that finished; the new
       * one is taken at a step boundary (background_lag). No element is re-rotated by the
       * steps themselves: the threshold is not used.
       */
      background
    };

    /** The matrix preconditioned CG solves with. */
    enum class Target
    {
      /** The exact corotational matrix, applied matrix-free over the elements. */
      corotational,
      /** The WCC matrix A (the assembled one). */
      warp_canceling
    };

    Kind         kind       = Kind::partial;
    Target       iterate_on = Target::corotational;
    /** CG stops at |b - B x| <= tolerance |b|. */
    double       cg_tolerance      = 1e-3;
    unsigned int max_cg_iterations = 100;
    /** delayed_top: the top is refreshed at least every this many steps. */
    unsigned int refresh_interval = 10;
    /** delayed_top: and after a solve that needed more than this many iterations. */
    unsigned int refresh_iterations = 8;
    /**
     * background: 0, a refresh is taken at the first step boundary after it finished (as
     * fast as the machine allows, the lag varying with it); N > 0, the refresh started at
     * step k is taken at step k + N, the step waiting for it if need be (the same bits
     * whatever the machine and the threads: tests, checkpoints).
     */
    unsigned int background_lag = 0;

    /** Whether the step's system is solved by preconditioned CG (all but partial). */
    bool iterates() const;
  };

  /** The names of the strategies (base/named_values.h): "partial", "delayed_top", "preconditioned", "auto", "background". */
  inline constexpr NameTable<StepStrategy::Kind, 5> step_strategy_names{
    {{StepStrategy::Kind::partial, "partial"},
     {StepStrategy::Kind::delayed_top, "delayed_top"},
     {StepStrategy::Kind::preconditioned, "preconditioned"},
     {StepStrategy::Kind::automatic, "auto"},
     {StepStrategy::Kind::background, "background"}}};
  /** The names of what CG iterates on: "corotational", "warp_canceling". */
  inline constexpr NameTable<StepStrategy::Target, 2> iteration_target_names{
    {{StepStrategy::Target::corotational, "corotational"}, {StepStrategy::Target::warp_canceling, "warp_canceling"}}};

  /** "partial", "delayed_top", "preconditioned", "auto", "background". */
  std::string to_string(StepStrategy::Kind kind);
  /** The inverse of to_string(); throws InputError listing the valid names. */
  StepStrategy::Kind parse_step_strategy(const std::string &name);
  /** "corotational", "warp_canceling". */
  std::string to_string(StepStrategy::Target target);
  StepStrategy::Target parse_iteration_target(const std::string &name);
  /** "all", "below_top", "none". */
  std::string to_string(cholesky::Refresh refresh);

  /**
   * The cost model of the automatic strategy: what a step will cost with each choice,
   * counting everything the step pays after the element pass (the estimate and the
   * re-assembly of WCC's updates, the factorization, the solve or CG's iterations), from
   * what was measured so far (exponential moving averages, so that it follows the run).
   *
   * Within a step that iterates, the refresh of the factor:
   *   seconds(refresh) = refresh seconds + iterations(refresh) * seconds per iteration,
   * with the refresh's seconds as the solver predicts them (its cheaper of updating the
   * factor and recomputing columns, at the rates it measured); the iterations after refreshing all or below the
   * top are those seen after the last such refreshes, with no refresh one more than the
   * last step's (the factor only grows staler).
   *
   * Between steps, when to make the factor exact (an exact step: every element re-rotated,
   * A assembled and factored in full, a direct solve): a refresh serves the steps after
   * it, which iterate the more the staler the factor is. With C the cost of an exact step
   * and c(s) that of a step s steps after it, a cycle of P steps costs on average
   *   a(P) = (C + c(1) + ... + c(P - 1)) / P,
   * least at some P*; the exact step is due as soon as the next step would cost more than
   * that least average, c(s + 1) > a(P*) (the rule of renewal: replace when the marginal
   * cost passes the least average cost). c(s) = o + i(s) t: the iterations i(s) are
   * measured per staleness s (counts: steadier than a step's seconds on a busy machine),
   * t is the seconds of one iteration and o the rest of an iterating step, both averaged
   * over every step; where i(s) was not measured yet, the last measured one stands for
   * it; an i(s) past the cycles of late is relaxed toward the last one seen at each exact
   * step (it may date from a cut), so that cycles grow again; and the rule reads the running
   * maximum of c over s (it assumes costs that do not fall as the factor ages: a cheaper
   * step later in the cycle, or noise, would otherwise make it refresh every step). When
   * c(s + 1) exceeds C the rule runs the exact step: never slower than exact, as far as
   * the measurements foresee.
   *
   * The machine only ever adds time to a step (a step held up by another process, the
   * first touches of a run's memory): a time under half its average replaces the average
   * instead of blending into it. And exact steps back to back measure no iterating step: a
   * model that overrates iterating, from one held-up step, would never learn better. After
   * iterating_probe_interval of them in a row, the next step iterates (a probe); the
   * interval doubles with each probe, so that where exact steps are right the probes cost
   * a share of the run that halves each time.
   */
  class StepCostModel
  {
  public:
    /** A solve after @p refresh took @p iterations iterations in @p seconds. */
    void record_iterations(cholesky::Refresh refresh, unsigned int iterations, double seconds);
    /**
     * An exact step cost @p seconds (assembly, factorization and solve); it ended a cycle
     * of @p cycle_length steps since the exact step before (what the last iterating step's
     * staleness was).
     */
    void record_exact_step(double seconds, unsigned int cycle_length);
    /**
     * An iterating step @p staleness steps after the last exact factor cost @p seconds
     * and @p iterations of CG.
     */
    void record_iterating_step(unsigned int staleness, double seconds, unsigned int iterations);
    /**
     * A step @p staleness steps after the last exact factor iterated @p iterations times,
     * and its seconds paid for more than iterating (a cut's or a grasp's refresh): the
     * iterations only.
     */
    void record_iterations_at(unsigned int staleness, unsigned int iterations);
    /**
     * A step of auto's own ran, @p exact or iterating (measured or not: one whose solve
     * failed and was made exact still iterated): counts the exact steps back to back.
     */
    void record_own_step(bool exact);

    /** The predicted seconds of a step whose refresh @p refresh costs @p refresh_seconds, then iterates. */
    double predicted_seconds(cholesky::Refresh refresh, double refresh_seconds) const;

    /**
     * The set-up's assembly and factorization of the rest matrix took @p step_seconds, its
     * factorization @p factorization_seconds (the whole factorize(), values loaded). The
     * first stands for an exact step until one is measured, which replaces it: the set-up
     * touches its memory first and runs slower than the exact steps after it.
     */
    void record_setup(double step_seconds, double factorization_seconds);
    /**
     * The set-up's factorization (record_setup(); negative before): the fall-back's stand-in
     * for the exact path's step until it measures one (ExactFallback), a part of such a step.
     * A measurement, not a rate: the solver learns the rates (SparseCholesky::cost_model()),
     * and at its rate, which the exact steps' warm factorizations lower, a factorization
     * without the step's assembly and solve would stand for less of the step than this and
     * probe the exact path where auto's own steps pay.
     */
    double setup_factorization_seconds() const;

    /** The predicted seconds of an exact step: the set-up's before one was measured (negative before either). */
    double predicted_exact_seconds() const;
    /**
     * The CG iterations that cost what an exact step does (0: not known yet). A step that
     * iterates past them has lost an exact step to iterating; made exact then, it costs
     * about two (the rule of the ski rental), however far CG would have gone.
     */
    unsigned int affordable_iterations() const;
    /** The predicted seconds of an iterating step @p staleness steps after the exact factor (negative if unknown). */
    double predicted_iterating_seconds(unsigned int staleness) const;

    /**
     * Whether the step @p staleness steps after the last exact factor should be exact
     * (the rule above); true before an exact step was measured, false before an
     * iterating one was. With @p steps_left (this one included; 0: not known) the run's
     * end is in view: an exact step is due only if it and the steps after it up to the
     * end cost less than iterating on to the end.
     */
    bool exact_step_is_due(unsigned int staleness, unsigned int steps_left = 0) const;

    /**
     * Whether enough was measured to weigh the refreshes of an iterating step: before that,
     * refresh all. The factorizations' rate is the solver's (@p factorization_rates,
     * SparseCholesky::cost_model()), which times every factorization it runs: a second
     * learner here, fed by the same factorizations, would only disagree with it.
     */
    bool calibrated(const cholesky::RefactorizationCostModel &factorization_rates) const;

    /** Write what was measured so far to a checkpoint. */
    void save(BinaryWriter &writer) const;
    void load(BinaryReader &reader);

  private:
    /** Staleness past this is counted as this. */
    static constexpr unsigned int longest_staleness = 64;
    /** Exact steps back to back before an iterating probe, at first and at the most. */
    static constexpr unsigned int shortest_probe_interval = 8, longest_probe_interval = 1024;

    double setup_factorization   = -1;
    double seconds_per_iteration = 0;
    double iterations_after_all  = 0;
    double iterations_after_top  = -1;
    double last_iterations       = 0;
    /** The exact steps measured (negative: none yet), and the set-up's stand-in for them. */
    double exact_seconds         = -1;
    double setup_exact_seconds   = -1;
    /** o: the seconds of an iterating step but its CG iterations. */
    double iterating_overhead    = -1;
    /** i(s) for s = 1 .. longest_staleness at [s - 1]; negative where not measured. */
    std::vector<double> iterations_at = std::vector<double>(longest_staleness, -1.);
    /** Exact steps back to back since the last iterating step, and the probes' interval. */
    unsigned int exact_steps_in_a_row     = 0;
    unsigned int iterating_probe_interval = shortest_probe_interval;
  };

  /**
   * Where the automatic strategy refreshes its factor when it has two threads or more:
   * in the steps, which then have every thread (the rule of renewal of StepCostModel),
   * or on a core of its own beside the steps (BackgroundRefresh), which then run on one
   * thread less. Neither wins everywhere. Beside the steps a refresh costs them a core:
   * it pays where CG iterates the more the staler the factor (thin bodies in bending),
   * and is a loss where the stale factor preconditions well anyway (the torus: about one
   * iteration a step) or where the steps' factorizations gain much from the second
   * thread. The two are not modelled but measured: each in turn for a window of steps,
   * then the one whose steps cost less on average for a stretch, after which the other
   * is tried again; the stretch doubles each time the other loses (the trials cost
   * little), and starts short again when it wins (the run has changed).
   */
  class RefreshPlacement
  {
  public:
    enum class Where
    {
      in_the_steps,
      beside_the_steps
    };

    /** Where the next steps' refreshes go. */
    Where current() const;

    /**
     * A step that ran with its refreshes where current() said cost @p seconds (its whole
     * work: element pass, refresh, solve); after it, current() may say otherwise.
     */
    void record_step(double seconds);

    /** Steps run so far with the refreshes in the steps and beside them. */
    unsigned int steps_in(Where where) const;

    void save(BinaryWriter &writer) const;
    void load(BinaryReader &reader);

  private:
    /** Steps of a trial; the first steps of a run (set-up, calibration) are not counted. */
    static constexpr unsigned int window = 8, first_counted_step = 3;
    /** The stretch after a trial, at first and at the most. */
    static constexpr unsigned int shortest_stretch = 48, longest_stretch = 768;

    Where        where          = Where::in_the_steps;
    /** Steps recorded, counted ones in the current phase and their seconds. */
    unsigned int steps          = 0;
    unsigned int phase_steps    = 0;
    double       phase_seconds  = 0;
    /** Whether the current phase is a trial (window steps) or a stretch of the winner. */
    bool         trial          = true;
    unsigned int stretch        = shortest_stretch;
    /** The mean seconds per step last measured in each place (negative: not yet). */
    double       mean_seconds[2] = {-1., -1.};
    unsigned int counts[2]       = {0, 0};
  };
  /**
   * What keeps the automatic strategy from losing to the exact path. It compares what its
   * own steps cost (whatever they chose: refreshes, CG, its own exact steps in WCC's
   * frames) with what the exact path's step costs (the corotational model's: element
   * rotations, A assembled in the elements' frames and factored in full, a direct solve),
   * both measured in the same run. The steps are the exact path's for a stretch, and
   * nothing more (no nodal rotation, no error estimate, no WCC frame, no cost model:
   * WarpCancelingModel::corotational_step()), as soon as
   * - a window of own steps and the one before it (unless a stretch came between) cost
   *   more than (1 + margin) times an exact step on average, by more than the standard
   *   error of their mean (own steps of a stale factor spread widely, a few dear ones
   *   among cheap ones, and one dear window of eight among cheap ones is no loss: a loss
   *   within the spread lets the window go on, up to longest_window steps, whose mean
   *   then decides),
   * - an own step of the first window after a stretch gave up its solve for an exact one, or
   * - what they cost over (1 + margin) times an exact step, summed over the steps since
   *   that sum last fell to zero (a CUSUM), exceeds one exact step: a loss that passes
   *   one step's cost ends the window at once, however early in it, and the window is
   *   then judged on its own steps (it has lost already: no spread to weigh).
   * Then the own steps get a window again.
   *
   * How long a stretch. Own steps that lose by a share l of an exact step end their next
   * window after k = min(window, 1 / (l - margin)) steps (the CUSUM passes one exact
   * step after 1 / (l - margin)), which cost k l exact steps more than the exact path;
   * the stretch is the shortest that makes that retry_budget of its time, S = k l /
   * retry_budget, at least shortest_stretch; while the own steps keep losing, at least
   * twice the last one (a run that does not change pays ever less for its retries); at
   * most longest_stretch. A window that wins ends the fall-back until the own steps lose
   * again.
   *
   * Before the exact path's step was measured, an estimate stands for it (the model's: the
   * smaller of the set-up's factorization and auto's own exact steps, which do more). The
   * set-up touches its memory first, and may cost far more than a later exact step: own
   * steps that do not cost less than 1 / estimate_doubt of it run a probe of a few exact
   * steps, which measures the reference; the stretch follows if they lose to it, the own
   * steps go on if they do not. While they win against a measured exact step, a probe measures it
   * again after an interval whose probe costs retry_budget of it, at least
   * shortest_stretch, doubling while they keep winning: one exact step measured on a
   * slow stretch of the machine does not keep the own steps on for the rest of the run.
   * Nor does the converse keep the exact path on: a stretch whose first window of exact
   * steps costs as much as the own steps that lost (their mean within the margin, their
   * spread aside) measured a slow spell of the machine, not a loss, and ends there.
   */
  class ExactFallback
  {
  public:
    /** Whether the next step should be the exact path's. */
    bool runs_exact() const;

    /**
     * What an exact step of the fall-back would cost, as far as the model can tell before
     * one ran (@p seconds; negative: nothing to tell): the reference until one is measured.
     */
    void set_exact_estimate(double seconds);

    /**
     * The step that runs_exact() was asked about cost @p seconds (its whole work: element
     * pass, refresh, solve): an exact one of the fall-back, or one of the strategy's own,
     * which @p solve_failed if its CG gave up for an exact step. An own step that
     * @p paid_for_a_change (a cut's or a grasp's columns refreshed) is not weighed: the
     * exact path's factorization absorbs a change for nothing, and the change's own
     * chooser already took the cheapest of update, partial and full refactorization.
     */
    void record_step(double seconds, bool solve_failed = false, bool paid_for_a_change = false);

    /** The mean seconds of the fall-back's last run of exact steps (negative: none yet). */
    double exact_step_seconds() const;
    /** The mean seconds of the last window of own steps (negative: none yet). */
    double own_step_seconds() const;
    /** The length of the current or last stretch of exact steps (0: none yet). */
    unsigned int stretch_length() const;

    /** Steps run exact by the fall-back (probes included), and how many stretches it ran. */
    unsigned int exact_steps() const;
    unsigned int fallbacks() const;
    /** How many of those stretches ended after their first window (the machine had slowed down). */
    unsigned int stretches_ended() const;

    void save(BinaryWriter &writer) const;
    void load(BinaryReader &reader);

    /**
     * Steps of a window of own steps, and of one whose loss is within its spread at the
     * most; the first steps of a run (set-up, calibration) are not counted.
     */
    static constexpr unsigned int window = 8, longest_window = 32, first_counted_step = 3;
    /** How many times an exact step the estimate may cost (the set-up's first touch of its memory). */
    static constexpr double estimate_doubt = 2;
    /** The exact steps of a probe, and the stretches at the least and the most. */
    static constexpr unsigned int probe = 2, shortest_stretch = 16, longest_stretch = 1024;
    /** Own steps must cost more than this share over an exact one to fall back. */
    static constexpr double margin = 0.02;
    /** The share of a stretch's time that the own steps after it may cost more than exact ones. */
    static constexpr double retry_budget = 0.01;

  private:
    /**
     * Whether own steps that cost @p seconds on average, with the standard error
     * @p error, lose to the reference: by more than the margin and the error.
     */
    bool own_steps_lose(double seconds, double error, double reference) const;
    /** Run exact steps for a stretch, its length from the own steps' loss. */
    void start_stretch();
    /** The own steps won against a measured exact step: when to measure it again (probe_interval). */
    void schedule_probe();

    bool         exact          = false;
    unsigned int steps          = 0;
    /** Steps and seconds of the current window or run of exact steps. */
    unsigned int phase_steps    = 0;
    double       phase_seconds  = 0;
    /** The sum of the squares of the own steps' seconds in the current window. */
    double       phase_squares  = 0;
    /** The window of own steps before the current one, since the last stretch (0 steps: none). */
    unsigned int earlier_steps   = 0;
    double       earlier_seconds = 0;
    double       earlier_squares = 0;
    /** The length of the current run of exact steps, and whether it is a probe. */
    unsigned int phase_length   = 0;
    bool         probing        = false;
    unsigned int stretch        = 0;
    /** Whether the current window of own steps follows a stretch (a loss then doubles it). */
    bool         after_stretch  = false;
    /** The mean of the last window of own steps (ended by its length or the CUSUM). */
    double       own_seconds    = -1;
    /** The standard error of that mean. */
    double       own_error      = 0;
    /** The own steps' CUSUM of seconds over (1 + margin) exact steps. */
    double       excess         = 0;
    /** The own steps of the current window that cost more than (1 + margin) exact steps. */
    unsigned int losing_steps   = 0;
    /** The mean of the last run of exact steps of the fall-back (negative: none yet). */
    double       exact_seconds  = -1;
    /** The model's estimate of an exact step, until one is measured. */
    double       estimate       = -1;
    unsigned int exact_count    = 0;
    unsigned int fallback_count = 0;
    /** Own steps between a won comparison and the next probe (0: none due), and those run since. */
    unsigned int probe_interval        = 0;
    unsigned int own_steps_since_probe = 0;
    /** Stretches ended after a window whose exact steps cost as much as the own steps that lost. */
    unsigned int stretches_ended_early = 0;
  };
} // namespace warpchol::fem
