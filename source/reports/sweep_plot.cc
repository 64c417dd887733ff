#include <warpchol/reports/sweep_plot.h>
#include <warpchol/base/format.h>
#include <warpchol/models/model_type.h>
#include <warpchol/reports/error_time_plot.h>

#include <algorithm>

namespace warpchol::app
{
  namespace
  {
    /** The legend entry of a row's model in the plot. */
    std::string plot_group(const std::string &model)
    {
      if (model == fem::to_string(fem::ModelType::warp_canceling))
        return "WCC partial";
      if (model == "wcc_target")
        return "WCC target error";
      if (model.rfind("wcc_", 0) == 0)
        return "WCC " + model.substr(4);
      return model;
    }
  } // namespace

  void write_sweep_plot(const std::string &csv_file, const AllParameters &parameters, const unsigned int n_unknowns,
                        const std::vector<SweepRow> &rows, const double exact_per_step, std::ostream &out)
  {
    const std::string stem = csv_file.size() > 4 && csv_file.compare(csv_file.size() - 4, 4, ".csv") == 0 ?
                               csv_file.substr(0, csv_file.size() - 4) :
                               csv_file;
    ErrorTimePlot plot(parameters.scene_name() + ": " + std::to_string(n_unknowns) + " unknowns, " +
                         std::to_string(parameters.time_stepping.n_steps) + " steps, " +
                         std::to_string(parameters.solver.settings.n_threads) +
                         " thread(s); error against the exact corotational run",
                       fem::to_string(fem::ModelType::corotational), exact_per_step);
    for (const auto &row : rows)
      if (&row != &rows.front() && row.failure.empty())
        plot.add({plot_group(row.model),
                  row.model == "wcc_target" ? format_number(100 * row.threshold) + "%" :
                                              (row.has_threshold ? format_number(row.threshold) : std::string()),
                  row.seconds / std::max(1u, row.steps),
                  row.error.max_error(), row.error.max_rms_error()});
    if (plot.write(stem + ".gp", stem + ".png", out))
      out << "plot: " << stem + ".png" << " (script " << stem + ".gp" << ")" << std::endl;
  }
} // namespace warpchol::app
