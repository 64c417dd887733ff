#pragma once

#include <warpchol/app/parameters.h>
#include <warpchol/reports/sweep_table.h>

#include <ostream>
#include <string>
#include <vector>

/**
 * @file
 * The plot of warpchol-threshold-sweep: error against seconds per step, one curve per
 * model or strategy (reports/error_time_plot.h draws it).
 */
namespace warpchol::app
{
  /**
   * Write the plot of @p rows (the first, the exact run, as the reference line at
   * @p exact_per_step seconds a step) beside @p csv_file: FILE.csv -> FILE.gp (the gnuplot
   * script) and FILE.png, and say so on @p out; @p n_unknowns: the scene's, for the title.
   */
  void write_sweep_plot(const std::string &csv_file, const AllParameters &parameters, unsigned int n_unknowns,
                        const std::vector<SweepRow> &rows, double exact_per_step, std::ostream &out);
} // namespace warpchol::app
