/**
 * warpchol-threshold-sweep: run a scene with warp-canceling corotation for a list of
 * update thresholds and compare each run with the exact corotational one: the trajectory
 * error against the run time (DESIGN.md section 5), as a table and a CSV file to plot.
 *
 *   warpchol-threshold-sweep PARAMS.prm [--thresholds 0,0.03,0.1,0.3,1,inf] [--csv FILE]
 *
 * The scene's model entries are overridden; its output entries are ignored. The CSV goes
 * to output/SCENE/threshold_sweep.csv unless --csv says otherwise.
 */

#include <warpchol/app/command_line.h>
#include <warpchol/app/output.h>
#include <warpchol/app/parameters.h>
#include <warpchol/app/scene.h>
#include <warpchol/base/atomic_file.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/stopwatch.h>

#include <deal.II/base/utilities.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace
{
  using namespace warpchol;

  const char *usage =
    "usage: warpchol-threshold-sweep PARAMS.prm [--thresholds T1,T2,...] [--csv FILE]\n"
    "  --thresholds  WCC update thresholds, numbers >= 0 or inf (default 0,0.03,0.1,0.3,1,inf)\n"
    "  --csv FILE    where the table goes as CSV (default output/SCENE/threshold_sweep.csv)";

  struct Options
  {
    std::string         parameter_file;
    std::vector<double> thresholds{0, 0.03, 0.1, 0.3, 1, std::numeric_limits<double>::infinity()};
    std::string         csv_file;
  };

  double parse_threshold(const std::string &text)
  {
    if (text == "inf" || text == "infinity")
      return std::numeric_limits<double>::infinity();
    std::size_t used  = 0;
    double      value = -1;
    try
      {
        value = std::stod(text, &used);
      }
    catch (...)
      {
        used = 0;
      }
    if (used != text.size() || !(value >= 0) || std::isinf(value))
      throw InputError("--thresholds: '" + text + "' is not a number >= 0 or inf");
    return value;
  }

  Options parse_command_line(const int argc, char **argv)
  {
    Options          options;
    app::CommandLine command_line(argc, argv);
    while (command_line.has_next())
      {
        const std::string argument = command_line.next();
        if (argument == "--thresholds")
          {
            options.thresholds.clear();
            for (const auto &text :
                 dealii::Utilities::split_string_list(command_line.value_of(argument), ','))
              options.thresholds.push_back(parse_threshold(text));
            if (options.thresholds.empty())
              throw InputError("--thresholds: no threshold given");
          }
        else if (argument == "--csv")
          options.csv_file = command_line.value_of(argument);
        else if (argument == "--help" || argument == "-h")
          {
            std::cout << usage << std::endl;
            std::exit(0);
          }
        else if (!argument.empty() && argument[0] != '-' && options.parameter_file.empty())
          options.parameter_file = argument;
        else
          throw InputError("unexpected argument '" + argument + "' (see --help)");
      }
    if (options.parameter_file.empty())
      throw InputError("no parameter file given (see --help)");
    return options;
  }

  /** One run of the sweep. */
  struct SweepRow
  {
    std::string  model;
    double       threshold           = 0;
    unsigned int steps               = 0;
    double       elements_updated    = 0; // mean percentage per step
    double       flops_recomputed    = 0; // mean percentage per step (0 without refactorization)
    double       seconds             = 0; // time steps only
    double       max_error           = 0;
    double       final_error         = 0;
    std::string  failure;
  };

  /** Run @p parameters' scene, comparing every step with @p reference (if not empty). */
  SweepRow run_scene(const app::AllParameters &parameters,
                     const std::vector<std::vector<fem::Vector3>> &reference,
                     std::vector<std::vector<fem::Vector3>>       *trajectory)
  {
    SweepRow row;
    row.model     = parameters.model.type;
    row.threshold = parameters.model.update_threshold;
    app::Scene  scene(parameters);
    const auto &rest = scene.body().rest_positions();
    for (unsigned int step = 1; step <= parameters.time_stepping.n_steps; ++step)
      {
        fem::StepStatistics statistics;
        Stopwatch           stopwatch;
        try
          {
            scene.integrator().advance(statistics);
          }
        catch (const MatrixError &error)
          {
            row.failure = error.what();
            break;
          }
        row.seconds += stopwatch.seconds();
        ++row.steps;
        row.elements_updated += 100.0 * statistics.elements_updated / scene.body().n_elements();
        if (statistics.refactorized)
          row.flops_recomputed += 100.0 * statistics.flops_recomputed / statistics.flops_full;
        const auto &x = scene.integrator().positions();
        if (trajectory)
          trajectory->push_back(x);
        if (!reference.empty())
          {
            double difference = 0, motion = 0;
            for (unsigned int v = 0; v < x.size(); ++v)
              {
                difference = std::max(difference, (x[v] - reference[step - 1][v]).norm());
                motion     = std::max(motion, (reference[step - 1][v] - rest[v]).norm());
              }
            row.final_error = motion > 0 ? difference / motion : difference;
            row.max_error   = std::max(row.max_error, row.final_error);
          }
      }
    if (row.steps > 0)
      {
        row.elements_updated /= row.steps;
        row.flops_recomputed /= row.steps;
      }
    return row;
  }

  void run(const Options &options)
  {
    app::AllParameters parameters(options.parameter_file);
    parameters.output.vtu_interval = 0;
    parameters.output.write_log    = false;

    // The exact run, recorded step by step.
    app::AllParameters corotational = parameters;
    corotational.model.type         = "corotational";
    std::vector<std::vector<fem::Vector3>> reference;
    const SweepRow exact = run_scene(corotational, {}, &reference);
    if (!exact.failure.empty())
      throw MatrixError("the corotational run: " + exact.failure);

    std::vector<SweepRow> rows{exact};
    for (const double threshold : options.thresholds)
      {
        app::AllParameters wcc     = parameters;
        wcc.model.type             = "warp_canceling";
        wcc.model.update_threshold = threshold;
        rows.push_back(run_scene(wcc, reference, nullptr));
        std::cerr << "threshold " << format_number(threshold) << " done" << std::endl;
      }

    std::ostringstream table;
    table << "model,threshold,steps,elements_updated_pct,flops_recomputed_pct,seconds,"
             "seconds_per_step,max_error_vs_corotational,final_error_vs_corotational,failure\n";
    std::cout << "scene " << parameters.scene_name() << ", " << parameters.time_stepping.n_steps
              << " steps; error = max_i |x_i - x_i(corotational)| / max_i |x_i(corotational) - X_i|\n"
              << std::setw(18) << "model" << std::setw(10) << "threshold" << std::setw(10)
              << "updated%" << std::setw(10) << "flops%" << std::setw(12) << "s/step"
              << std::setw(12) << "max error" << std::setw(12) << "end error" << "\n";
    for (const auto &row : rows)
      {
        const double per_step = row.steps > 0 ? row.seconds / row.steps : 0;
        table << row.model << "," << format_number(row.threshold) << "," << row.steps << ","
              << format_number(row.elements_updated, 4) << "," << format_number(row.flops_recomputed, 4)
              << "," << format_number(row.seconds, 4) << "," << format_number(per_step, 4) << ","
              << format_number(row.max_error, 3) << "," << format_number(row.final_error, 3) << ","
              << (row.failure.empty() ? "" : "\"" + row.failure + "\"") << "\n";
        std::cout << std::setw(18) << row.model << std::setw(10)
                  << (row.model == "warp_canceling" ? format_number(row.threshold) : "-")
                  << std::setw(10) << format_number(row.elements_updated, 3) << std::setw(10)
                  << format_number(row.flops_recomputed, 3) << std::setw(12)
                  << format_number(per_step, 3) << std::setw(12) << format_number(row.max_error, 2)
                  << std::setw(12) << format_number(row.final_error, 2)
                  << (row.failure.empty() ? "" : "  " + row.failure) << "\n";
      }
    std::string csv_file = options.csv_file;
    if (csv_file.empty())
      {
        const std::string directory = parameters.output.directory + "/" + parameters.scene_name();
        app::create_directory(directory);
        csv_file = directory + "/threshold_sweep.csv";
      }
    write_file_atomically(csv_file, [&](std::ostream &out) { out << table.str(); });
    std::cout << "table: " << csv_file << std::endl;
  }
} // namespace

int main(int argc, char **argv)
{
  return warpchol::app::run_program("warpchol-threshold-sweep",
                                    [&] { run(parse_command_line(argc, argv)); });
}
