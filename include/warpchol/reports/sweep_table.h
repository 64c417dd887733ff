#pragma once

#include <warpchol/app/parameters.h>
#include <warpchol/app/trajectory_error.h>
#include <warpchol/dynamics/implicit_euler.h>

#include <ostream>
#include <string>
#include <vector>

/**
 * @file
 * The results of warpchol-threshold-sweep: one row per run (a WCC threshold, strategy or
 * target, a peer), printed as a table with the best runs, and written as CSV.
 */
namespace warpchol::app
{
  /** One run of the sweep. */
  struct SweepRow
  {
    std::string         model;
    double              threshold        = 0;
    unsigned int        steps            = 0;
    double              elements_rerotated = 0; // mean percentage per step
    double              flops_recomputed = 0; // mean percentage per step (0 without refactorization)
    double              cg_iterations    = 0; // mean per step
    double              seconds          = 0; // time steps only
    double              factor_mib       = 0; // the factor's or preconditioner's memory
    double              cg_iteration_mb  = 0; // what one CG iteration moves (0 without CG)
    double              cg_gbps          = 0; // and at what rate its iterations moved it
    bool                has_threshold    = false; // a WCC threshold or target, or a peer's tolerance
    fem::StepStatistics phases;               // seconds summed over the steps
    TrajectoryError     error;                // against the exact run (none for itself)
    std::string         failure;
  };

  /** The threshold column: the WCC threshold or target, the peer's tolerance, or "-". */
  std::string threshold_text(const SweepRow &row);

  /**
   * The table on @p out: per run the updates, the flops, CG's iterations, the
   * time per step and its split by phase, and the trajectory error against the exact run
   * (the first row): the worst vertex's error, largest and mean over the steps, and the
   * RMS error, largest and mean over the steps (PositionError).
   */
  void print_sweep_table(std::ostream &out, const AllParameters &parameters, const std::vector<SweepRow> &rows,
                         double exact_per_step);

  /**
   * One line per figure of the study (doc/strategies.md): the fastest run whose largest error stays
   * at or below 1 %, and the automatic and background strategies' best runs, each with its
   * speed-up against the exact run (the first row), error and CG iterations.
   */
  void print_sweep_best(std::ostream &out, const std::vector<SweepRow> &rows, double exact_per_step);

  /** The table as CSV, one row per run, with the error at the last step too. */
  void write_sweep_csv(const std::vector<SweepRow> &rows, std::ostream &out);
} // namespace warpchol::app
