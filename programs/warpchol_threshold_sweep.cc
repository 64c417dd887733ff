/**
 * warpchol-threshold-sweep: run a scene with warp-canceling corotation for a list of
 * re-rotation thresholds and step strategies, and compare each run with the exact corotational
 * one: the trajectory error against the run time (DESIGN.md section 5), as a table, a
 * CSV file and a plot (PNG, drawn by gnuplot from a script written beside the CSV), with
 * the per-phase split of a step and the cost per element of the element kernels (ns per
 * tet).
 *
 *   warpchol-threshold-sweep PARAMS.prm [--thresholds 0,0.03,0.1,0.3,1,inf]
 *       [--strategies delayed_top,preconditioned,auto] [--strategy-thresholds 0.3,1,inf]
 *       [--target-errors 0.003,0.01,0.03] [--backends all|B1,B2,...]
 *       [--peer-tolerances 1e-6,1e-3] [--threads N] [--csv FILE]
 *
 * The partial strategy (direct solve of the WCC system) runs at every --thresholds; each
 * of --strategies at every --strategy-thresholds, with the scene's CG settings; the partial
 * strategy with each of --target-errors (Model/Target error, from threshold 0.3), rows
 * wcc_target whose threshold column is the target; each peer of --backends (Solver/Backend)
 * on the exact corotational model, the iterative ones at each of --peer-tolerances, rows
 * named by the backend whose threshold column is the tolerance. The
 * scene's model entries are overridden; its output entries are ignored. The CSV goes to
 * output/SCENE/threshold_sweep.csv unless --csv says otherwise; beside it, with the same
 * name, the gnuplot script (.gp) and the plot (.png) of error against seconds per step.
 */

#include <warpchol/app/command_line.h>
#include <warpchol/app/output.h>
#include <warpchol/app/parameters.h>
#include <warpchol/app/scene.h>
#include <warpchol/app/trajectory_error.h>
#include <warpchol/backends/linear_solver.h>
#include <warpchol/base/atomic_file.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/cholesky/blas.h>
#include <warpchol/reports/machine.h>
#include <warpchol/reports/sweep_kernel_timing.h>
#include <warpchol/reports/sweep_plot.h>
#include <warpchol/reports/sweep_table.h>

#include <deal.II/base/utilities.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

namespace
{
  using namespace warpchol;

  const char *usage =
    "usage: warpchol-threshold-sweep PARAMS.prm [--thresholds T1,T2,...] [--strategies S1,...]\n"
    "                                [--strategy-thresholds T1,...] [--target-errors E1,...]\n"
    "                                [--backends all|B1,...] [--peer-tolerances T1,...]\n"
    "                                [--threads N] [--csv FILE]\n"
    "  --thresholds           WCC thresholds of the partial strategy, numbers >= 0 or inf\n"
    "                         (default 0,0.03,0.1,0.3,1,inf)\n"
    "  --strategies           the other step strategies to run (default\n"
    "                         delayed_top,preconditioned,auto; also background (once: it\n"
    "                         uses no threshold); 'none' for none)\n"
    "  --strategy-thresholds  their thresholds (default 0.3,1,inf)\n"
    "  --target-errors        WCC target errors (partial strategy, the threshold adapted;\n"
    "                         default none)\n"
    "  --backends             the peers to run the exact corotational model with (Solver/\n"
    "                         Backend; 'all' for every one but warpchol; default none)\n"
    "  --peer-tolerances      the tolerances of the iterative peers (default 1e-6,1e-3)\n"
    "  --threads N            Solver/Threads of every run (default: the scene's)\n"
    "  --csv FILE             where the table goes as CSV (default output/SCENE/threshold_sweep.csv);\n"
    "                         the plot of error against time goes beside it, FILE.png drawn by\n"
    "                         gnuplot from the script FILE.gp (FILE without .csv)";

  struct Options
  {
    std::string         parameter_file;
    std::vector<double> thresholds{0, 0.03, 0.1, 0.3, 1, std::numeric_limits<double>::infinity()};
    std::vector<fem::StepStrategy::Kind> strategies{fem::StepStrategy::Kind::delayed_top,
                                                    fem::StepStrategy::Kind::preconditioned,
                                                    fem::StepStrategy::Kind::automatic};
    std::vector<double> strategy_thresholds{0.3, 1, std::numeric_limits<double>::infinity()};
    std::vector<double> target_errors;
    std::vector<backends::Backend> peers;
    std::vector<double> peer_tolerances{1e-6, 1e-3};
    unsigned int        threads = 0;
    std::string         csv_file;
  };

  std::vector<double> parse_thresholds(const std::string &option, const std::string &list)
  {
    std::vector<double> thresholds;
    for (const auto &text : dealii::Utilities::split_string_list(list, ','))
      {
        double threshold = 0;
        if (!app::parse_threshold(text, threshold))
          throw InputError(option + ": '" + text + "' is not a number >= 0 or inf");
        thresholds.push_back(threshold);
      }
    if (thresholds.empty())
      throw InputError(option + ": no threshold given");
    return thresholds;
  }

  /** A list of numbers in (0, 1) given to @p option: target errors, tolerances. */
  std::vector<double> parse_fractions(const std::string &option, const std::string &list)
  {
    std::vector<double> values = parse_thresholds(option, list);
    for (const double value : values)
      if (!(value > 0 && value < 1))
        throw InputError(option + ": " + format_number(value) + " is not in (0, 1)");
    return values;
  }

  Options parse_command_line(const int argc, char **argv)
  {
    Options          options;
    app::CommandLine command_line(argc, argv);
    while (command_line.has_next())
      {
        const std::string argument = command_line.next();
        if (argument == "--thresholds")
          options.thresholds = parse_thresholds(argument, command_line.value_of(argument));
        else if (argument == "--strategy-thresholds")
          options.strategy_thresholds = parse_thresholds(argument, command_line.value_of(argument));
        else if (argument == "--target-errors")
          options.target_errors = parse_fractions(argument, command_line.value_of(argument));
        else if (argument == "--strategies")
          {
            options.strategies.clear();
            const std::string list = command_line.value_of(argument);
            if (list != "none")
              for (const auto &text : dealii::Utilities::split_string_list(list, ','))
                {
                  const auto kind = fem::parse_step_strategy(text);
                  if (kind == fem::StepStrategy::Kind::partial)
                    throw InputError("--strategies: partial runs at every --thresholds already");
                  options.strategies.push_back(kind);
                }
          }
        else if (argument == "--backends")
          {
            const std::string list = command_line.value_of(argument);
            options.peers.clear();
            for (const auto &text : dealii::Utilities::split_string_list(list, ','))
              if (text == "all")
                for (const auto backend : backends::all_backends())
                  options.peers.push_back(backend);
              else
                options.peers.push_back(backends::parse_backend(text));
            // warpchol's own exact run is the first row already.
            options.peers.erase(std::remove(options.peers.begin(), options.peers.end(), backends::Backend::warpchol),
                                options.peers.end());
          }
        else if (argument == "--peer-tolerances")
          options.peer_tolerances = parse_fractions(argument, command_line.value_of(argument));
        else if (argument == "--threads")
          {
            const std::string text = command_line.value_of(argument);
            if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos ||
                std::stoul(text) < 1 || std::stoul(text) > 1024)
              throw InputError("--threads: '" + text + "' is not a number of threads in [1, 1024]");
            options.threads = std::stoul(text);
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

  /** The name of a run in the model column: the model, or the WCC strategy. */
  std::string row_name(const app::AllParameters &parameters)
  {
    if (parameters.solver.backend.backend != backends::Backend::warpchol)
      return backends::to_string(parameters.solver.backend.backend);
    const auto kind = parameters.model.strategy.kind;
    if (parameters.model.type == fem::ModelType::warp_canceling && parameters.model.target_error > 0)
      return "wcc_target";
    if (parameters.model.type != fem::ModelType::warp_canceling || kind == fem::StepStrategy::Kind::partial)
      return fem::to_string(parameters.model.type);
    return "wcc_" + fem::to_string(kind);
  }

  /** Run @p parameters' scene, comparing every step with @p reference (if not empty). */
  app::SweepRow run_scene(const app::AllParameters &parameters,
                          const std::vector<std::vector<fem::Vector3>> &reference,
                          std::vector<std::vector<fem::Vector3>>       *trajectory)
  {
    app::SweepRow row;
    row.model     = row_name(parameters);
    row.threshold = parameters.model.target_error > 0 ? parameters.model.target_error :
                                                         parameters.model.rerotation_threshold;
    row.has_threshold = parameters.model.type == fem::ModelType::warp_canceling &&
                        parameters.model.strategy.kind != fem::StepStrategy::Kind::background;
    if (backends::iterates(parameters.solver.backend.backend))
      {
        row.threshold     = parameters.solver.backend.tolerance;
        row.has_threshold = true;
      }
    app::Scene  scene(parameters);
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
        row.elements_rerotated += 100.0 * statistics.elements_rerotated / scene.body().n_elements();
        if (statistics.refactorized)
          row.flops_recomputed += 100.0 * statistics.flops_recomputed / statistics.flops_full;
        row.cg_iterations += statistics.cg_iterations;
        row.phases.add_phase_times(statistics);
        const auto &x = scene.integrator().positions();
        if (trajectory)
          trajectory->push_back(x);
        if (!reference.empty())
          row.error.add(app::position_error(x, reference[step - 1], scene.body().rest_positions()));
      }
    row.factor_mib = scene.model().factor_memory_bytes() / 1048576.;
    if (scene.model().cg_bytes_per_second() > 0)
      {
        row.cg_iteration_mb = scene.model().cg_iteration_bytes().total() * 1e-6;
        row.cg_gbps         = scene.model().cg_bytes_per_second() * 1e-9;
      }
    if (row.steps > 0)
      {
        row.elements_rerotated /= row.steps;
        row.flops_recomputed /= row.steps;
        row.cg_iterations /= row.steps;
      }
    return row;
  }

  void run(const Options &options)
  {
    app::AllParameters parameters(options.parameter_file);
    parameters.output.vtu_interval = 0;
    parameters.output.write_log    = false;
    if (options.threads > 0)
      parameters.solver.settings.n_threads = options.threads;
    // Where the CSV and the plot go: the folder is made now, not after minutes of runs.
    const std::string csv_file = options.csv_file.empty() ?
                                   parameters.output.directory + "/" + parameters.scene_name() +
                                     "/threshold_sweep.csv" :
                                   options.csv_file;
    const std::string csv_directory = std::filesystem::path(csv_file).parent_path().string();
    if (!csv_directory.empty())
      app::create_directory(csv_directory);

    // The exact run, recorded step by step, after a few steps of it that warm the machine
    // up: the first run of a process pays for its caches, pages and clock ramp-up.
    const app::AllParameters corotational = parameters.exact_corotational();
    {
      app::AllParameters warm_up           = corotational;
      warm_up.time_stepping.n_steps = std::min(5u, parameters.time_stepping.n_steps);
      run_scene(warm_up, {}, nullptr);
    }
    std::vector<std::vector<fem::Vector3>> reference;
    const app::SweepRow exact = run_scene(corotational, {}, &reference);
    if (!exact.failure.empty())
      throw MatrixError("the corotational run: " + exact.failure);

    std::vector<app::AllParameters> runs;
    for (const double threshold : options.thresholds)
      {
        app::AllParameters wcc     = parameters;
        wcc.model.type             = fem::ModelType::warp_canceling;
        wcc.model.rerotation_threshold = threshold;
        wcc.model.target_error     = 0; // a fixed threshold, whatever the scene says
        wcc.model.strategy.kind    = fem::StepStrategy::Kind::partial;
        runs.push_back(wcc);
      }
    for (const auto kind : options.strategies)
      for (const double threshold : options.strategy_thresholds)
        {
          app::AllParameters wcc     = parameters;
          wcc.model.type             = fem::ModelType::warp_canceling;
          wcc.model.rerotation_threshold = threshold;
          wcc.model.target_error     = 0;
          wcc.model.strategy.kind    = kind;
          wcc.model.strategy.iterate_on = fem::StepStrategy::Target::corotational;
          runs.push_back(wcc);
          // The background refresh estimates nothing: one run, whatever the thresholds.
          if (kind == fem::StepStrategy::Kind::background)
            break;
        }
    for (const auto backend : options.peers)
      {
        app::AllParameters peer      = parameters.exact_corotational();
        peer.solver.backend.backend  = backend;
        if (!backends::iterates(backend))
          runs.push_back(peer);
        else
          for (const double tolerance : options.peer_tolerances)
            {
              peer.solver.backend.tolerance = tolerance;
              runs.push_back(peer);
            }
      }
    for (const double target : options.target_errors)
      {
        app::AllParameters wcc     = parameters;
        wcc.model.type             = fem::ModelType::warp_canceling;
        wcc.model.rerotation_threshold = 0.3;
        wcc.model.target_error     = target;
        wcc.model.strategy.kind    = fem::StepStrategy::Kind::partial;
        runs.push_back(wcc);
      }
    std::vector<app::SweepRow> rows{exact};
    for (const auto &run_parameters : runs)
      {
        rows.push_back(run_scene(run_parameters, reference, nullptr));
        std::cerr << rows.back().model << " " << format_number(rows.back().threshold) << " done" << std::endl;
      }

    const double exact_per_step = exact.seconds / std::max(1u, exact.steps);
    app::print_sweep_table(std::cout, parameters, rows, exact_per_step);
    app::print_sweep_best(std::cout, rows, exact_per_step);
    // The ceiling of every factorization on this machine, to read the times against.
    std::cout << app::describe_machine() << "\n";
    const app::Scene scene(corotational);
    app::print_sweep_kernel_table(std::cout, scene, reference.back(), rows);
    write_file_atomically(csv_file, [&](std::ostream &out) { app::write_sweep_csv(rows, out); });
    std::cout << "table: " << csv_file << std::endl;

    // The plot beside the CSV: FILE.csv -> FILE.gp, FILE.png.
    app::write_sweep_plot(csv_file, parameters, scene.body().n_unknowns(), rows, exact_per_step, std::cout);
  }
} // namespace

int main(int argc, char **argv)
{
  // As the solver benchmarks: OpenBLAS's worker threads and CHOLMOD's OpenMP regions would
  // compete with the scene's own threads.
  warpchol::cholesky::blas::restart_with_single_threaded_libraries(argv);
  return warpchol::app::run_program("warpchol-threshold-sweep",
                                    [&] { run(parse_command_line(argc, argv)); });
}
