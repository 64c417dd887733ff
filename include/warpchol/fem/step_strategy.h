#pragma once

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
      automatic
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

    /** Whether the step's system is solved by preconditioned CG (all but partial). */
    bool iterates() const;
  };

  /** "partial", "delayed_top", "preconditioned", "auto". */
  std::string to_string(StepStrategy::Kind kind);
  /** The inverse of to_string(); throws InputError listing the valid names. */
  StepStrategy::Kind parse_step_strategy(const std::string &name);
  /** "corotational", "warp_canceling". */
  std::string to_string(StepStrategy::Target target);
  StepStrategy::Target parse_iteration_target(const std::string &name);
  /** "all", "below_top", "none". */
  std::string to_string(cholesky::Refresh refresh);

  /**
   * The cost model of the automatic strategy: what a step will cost with each refresh,
   *   seconds(refresh) = flops(refresh) / flop rate + iterations(refresh) * seconds per iteration,
   * with the flops the solver predicts, and the rates and iteration counts measured so far
   * (exponential moving averages, so they follow the run). The iterations expected after
   * refreshing all or below the top are those seen after the last such refreshes; with no
   * refresh, one more than the last step's (the factor only grows staler).
   */
  class RefreshCostModel
  {
  public:
    /** A factorization of @p flops took @p seconds. */
    void record_factorization(double flops, double seconds);
    /** A solve after @p refresh took @p iterations iterations in @p seconds. */
    void record_iterations(cholesky::Refresh refresh, unsigned int iterations, double seconds);

    /** The predicted seconds of a step that refreshes with @p refresh at @p flops. */
    double predicted_seconds(cholesky::Refresh refresh, double flops) const;

    /** Whether enough was measured to predict: before that, refresh all. */
    bool calibrated() const;

    /** Write what was measured so far to a checkpoint. */
    void save(BinaryWriter &writer) const;
    void load(BinaryReader &reader);

  private:
    double flop_rate            = 0;
    double seconds_per_iteration = 0;
    double iterations_after_all  = 0;
    double iterations_after_top  = -1;
    double last_iterations       = 0;
  };
} // namespace warpchol::fem
