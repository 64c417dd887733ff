/**
 * warpchol-surgery: what cuts, grasps and material changes cost (issue 19), against a full
 * factorization and against the peers, on a scene with such changes.
 *
 *   warpchol-surgery PARAMS.prm [--repeat R] [--csv FILE]
 *
 * 1. Each change alone: the scene with stiffness warping (WCC at threshold inf, partial
 *    strategy), whose factor changes only with the changes. At each step with a change:
 *    the elements cut or changed and vertices grasped or released, the columns it touched
 *    and the flops of refactorizing them (% of a full factorization), the seconds of that
 *    partial refactorization, of a full one of the same matrix (warpchol), and of CHOLMOD
 *    analyzing anew and factoring it (as SOFA does after a topological change); and the
 *    check partial <= 1.2 x flop fraction x full + 1 ms.
 * 2. Whole runs, seconds per step: the scene as its parameters say; the same without the
 *    changes; exact corotation refactored every step by warpchol and by CHOLMOD (which
 *    analyzes anew after each cut); the stale rest factor as CG's preconditioner (SOFA's
 *    warp preconditioner, to the scene's CG tolerance) with its iterations per step
 *    before the first change and after the last.
 * Output is switched off; the CSV (default output/SCENE/surgery.csv) has the first table.
 */

#include <warpchol/app/command_line.h>
#include <warpchol/app/parameters.h>
#include <warpchol/app/scene.h>
#include <warpchol/app/output.h>
#include <warpchol/base/atomic_file.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/backends/linear_solver.h>
#include <warpchol/cholesky/blas.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace
{
  using namespace warpchol;

  const char *usage = "usage: warpchol-surgery PARAMS.prm [--repeat R] [--csv FILE]";

  struct Options
  {
    std::string  parameter_file;
    unsigned int repeat = 3;
    std::string  csv_file;
  };

  Options parse_command_line(const int argc, char **argv)
  {
    Options          options;
    app::CommandLine command_line(argc, argv);
    while (command_line.has_next())
      {
        const std::string argument = command_line.next();
        if (argument == "--repeat")
          options.repeat = command_line.integer_of(argument, 1, 100);
        else if (argument == "--csv")
          options.csv_file = command_line.value_of(argument);
        else
          command_line.read_help_or_input_file(argument, usage, options.parameter_file);
      }
    if (options.parameter_file.empty())
      throw InputError("no parameter file given (see --help)");
    return options;
  }

  /** The best of @p repeat runs of @p action, in seconds. */
  double best_of(const unsigned int repeat, const std::function<void()> &action)
  {
    double best = std::numeric_limits<double>::infinity();
    for (unsigned int r = 0; r < repeat; ++r)
      {
        const Stopwatch stopwatch;
        action();
        best = std::min(best, stopwatch.seconds());
      }
    return best;
  }

  /** What one change step cost. */
  struct ChangeRow
  {
    unsigned int step = 0;
    std::string  what;
    double       columns_pct = 0, flops_pct = 0;
    double       partial = 0, full = 0, cholmod = 0;
  };

  /** Seconds per step of a whole run, and CG's iterations per step. */
  struct RunRow
  {
    std::string               name;
    double                    seconds_per_step = 0;
    double                    iterations       = 0;
    std::vector<unsigned int> iterations_per_step;
    std::vector<bool>         changed;
  };

  RunRow run_scene(const std::string &name, const app::AllParameters &parameters)
  {
    app::Scene scene(parameters);
    RunRow     row;
    row.name = name;
    double seconds = 0;
    for (unsigned int step = 0; step < parameters.time_stepping.n_steps; ++step)
      {
        fem::StepStatistics statistics;
        const Stopwatch     stopwatch;
        scene.integrator().advance(statistics);
        seconds += stopwatch.seconds();
        row.iterations += statistics.cg_iterations;
        row.iterations_per_step.push_back(statistics.cg_iterations);
        row.changed.push_back(statistics.change_columns > 0);
      }
    row.seconds_per_step = seconds / parameters.time_stepping.n_steps;
    row.iterations /= parameters.time_stepping.n_steps;
    return row;
  }

  std::vector<ChangeRow> change_costs(const app::AllParameters &scene_parameters, const unsigned int repeat)
  {
    app::AllParameters parameters      = scene_parameters;
    parameters.model.type              = "warp_canceling";
    parameters.model.update_threshold  = std::numeric_limits<double>::infinity();
    parameters.model.target_error      = 0;
    parameters.model.strategy.kind     = fem::StepStrategy::Kind::partial;
    parameters.solver.backend.backend  = backends::Backend::warpchol;
    app::Scene             scene(parameters);
    std::vector<ChangeRow> rows;
    for (unsigned int step = 1; step <= parameters.time_stepping.n_steps; ++step)
      {
        fem::StepStatistics statistics;
        scene.integrator().advance(statistics);
        if (statistics.change_columns == 0)
          continue;
        ChangeRow row;
        row.step = step;
        std::ostringstream what;
        if (statistics.elements_cut > 0)
          what << statistics.elements_cut << " cut ";
        if (statistics.vertices_grasped > 0)
          what << statistics.vertices_grasped << " grasped ";
        if (statistics.vertices_released > 0)
          what << statistics.vertices_released << " released ";
        if (statistics.elements_changed > 0)
          what << statistics.elements_changed << " changed ";
        row.what        = what.str();
        row.columns_pct = 100.0 * statistics.change_columns / statistics.n_columns;
        row.flops_pct   = 100.0 * statistics.change_flops / statistics.flops_full;
        row.partial     = statistics.t_factor();
        // The same matrix factored in full, by warpchol and by CHOLMOD analyzing anew.
        const auto &model  = scene.model();
        auto        fresh  = model.solver();
        row.full           = best_of(repeat, [&] { fresh.factorize(model.system_matrix().lower()); });
        backends::Settings cholmod_settings;
        cholmod_settings.backend = backends::Backend::cholmod;
        auto cholmod             = backends::create_linear_solver(cholmod_settings, {});
        row.cholmod              = best_of(repeat, [&] {
          cholmod->topology_changed();
          cholmod->factorize(model.system_matrix().matrix(), model.system_matrix().csc());
        });
        rows.push_back(row);
      }
    return rows;
  }

  void run(const Options &options)
  {
    app::AllParameters parameters(options.parameter_file);
    parameters.output.vtu_interval = 0;
    parameters.output.write_log    = false;
    const std::string csv_file     = options.csv_file.empty() ?
                                       parameters.output.directory + "/" + parameters.scene_name() + "/surgery.csv" :
                                       options.csv_file;
    const std::string csv_directory = std::filesystem::path(csv_file).parent_path().string();
    if (!csv_directory.empty())
      app::create_directory(csv_directory);

    std::cout << "scene " << parameters.scene_name() << ", " << parameters.time_stepping.n_steps << " steps, "
              << parameters.solver.settings.n_threads << " thread(s)\n\n"
              << "each change alone (stiffness warping: the factor changes only with the changes); seconds, best of "
              << options.repeat << "\n"
              << std::setw(6) << "step" << std::setw(26) << "change" << std::setw(10) << "columns%" << std::setw(9)
              << "flops%" << std::setw(11) << "partial s" << std::setw(10) << "full s" << std::setw(11) << "CHOLMOD s"
              << std::setw(14) << "partial/full" << std::setw(15) << "bound/full" << std::setw(14) << "CHOLMOD/part"
              << "\n";
    const std::vector<ChangeRow> changes = change_costs(parameters, options.repeat);
    unsigned int                 within  = 0;
    for (const auto &row : changes)
      {
        const double bound = 1.2 * row.flops_pct / 100 * row.full + 1e-3;
        within += row.partial <= bound;
        std::cout << std::setw(6) << row.step << std::setw(26) << row.what << std::setw(10)
                  << format_number(row.columns_pct, 3) << std::setw(9) << format_number(row.flops_pct, 3) << std::setw(11)
                  << format_number(row.partial, 3) << std::setw(10) << format_number(row.full, 3) << std::setw(11)
                  << format_number(row.cholmod, 3) << std::setw(14) << format_number(row.partial / row.full, 3)
                  << std::setw(15) << format_number(1.2 * row.flops_pct / 100 + 1e-3 / row.full, 3) << std::setw(14)
                  << format_number(row.cholmod / row.partial, 3) << "\n";
      }
    std::cout << "steps with a change within 1.2 x flop fraction x full + 1 ms: " << within << " of " << changes.size()
              << "\n\n";

    // Whole runs.
    std::vector<RunRow> runs;
    runs.push_back(run_scene("as the scene says (" + parameters.model.type + ", " +
                               fem::to_string(parameters.model.strategy.kind) + ")",
                             parameters));
    app::AllParameters unchanged = parameters;
    unchanged.cut.duration       = 0;
    unchanged.grasp.sphere_radius = 0;
    unchanged.material_change.region.kind = "none";
    runs.push_back(run_scene("the same without the changes", unchanged));
    runs.push_back(run_scene("exact, warpchol refactoring every step", parameters.exact_corotational()));
    app::AllParameters cholmod = parameters.exact_corotational();
    cholmod.solver.backend.backend = backends::Backend::cholmod;
    runs.push_back(run_scene("exact, CHOLMOD refactoring every step (anew after a cut)", cholmod));
    app::AllParameters stale = parameters.exact_corotational();
    stale.solver.backend.backend   = backends::Backend::warp_preconditioned_cg;
    stale.solver.backend.tolerance = parameters.model.strategy.cg_tolerance;
    runs.push_back(run_scene("stale rest factor + CG to " + format_number(parameters.model.strategy.cg_tolerance, 2) +
                               " (SOFA's warp preconditioner)",
                             stale));

    std::cout << "whole runs" << "\n"
              << std::setw(62) << "run" << std::setw(10) << "s/step" << std::setw(10) << "steps/s" << std::setw(8) << "CG it"
              << std::setw(22) << "first / this s/step" << "\n";
    for (const auto &row : runs)
      std::cout << std::setw(62) << row.name << std::setw(10) << format_number(row.seconds_per_step, 3) << std::setw(10)
                << format_number(1 / row.seconds_per_step, 3) << std::setw(8) << format_number(row.iterations, 3)
                << std::setw(22) << format_number(row.seconds_per_step / runs.front().seconds_per_step, 3) << "\n";
    // The stale factor's iterations before the first change and after the last.
    const RunRow &stale_run = runs.back();
    const auto    first     = std::find(stale_run.changed.begin(), stale_run.changed.end(), true) - stale_run.changed.begin();
    const auto    last      = stale_run.changed.rend() - std::find(stale_run.changed.rbegin(), stale_run.changed.rend(), true);
    const auto    mean      = [&](const std::size_t begin, const std::size_t end) {
      double sum = 0;
      for (std::size_t k = begin; k < end; ++k)
        sum += stale_run.iterations_per_step[k];
      return end > begin ? sum / (end - begin) : 0.0;
    };
    std::cout << "stale rest factor: CG iterations per step " << format_number(mean(0, first), 3)
              << " before the first change, " << format_number(mean(last, stale_run.changed.size()), 3)
              << " after the last\n"
              << "the changes' run at " << format_number(100 * runs[1].seconds_per_step / runs[0].seconds_per_step, 3)
              << " % of the steps per second without them; " << format_number(runs[3].seconds_per_step / runs[0].seconds_per_step, 3)
              << "x faster than CHOLMOD refactoring every step, "
              << format_number(runs[4].seconds_per_step / runs[0].seconds_per_step, 3)
              << "x faster than the stale rest factor\n";

    write_file_atomically(csv_file, [&](std::ostream &out) {
      out << "step,change,columns_pct,flops_pct,partial_seconds,full_seconds,cholmod_seconds\n";
      for (const auto &row : changes)
        out << row.step << "," << row.what << "," << row.columns_pct << "," << row.flops_pct << "," << row.partial << ","
            << row.full << "," << row.cholmod << "\n";
    });
    std::cout << "table: " << csv_file << std::endl;
  }
} // namespace

int main(int argc, char **argv)
{
  warpchol::cholesky::blas::restart_with_single_threaded_libraries(argv);
  return warpchol::app::run_program("warpchol-surgery", [&] { run(parse_command_line(argc, argv)); });
}
