/**
 * warpchol-surgery: what cuts, grasps and material changes cost (issue 19), against a full
 * factorization and against the peers, on a scene with such changes.
 *
 *   warpchol-surgery PARAMS.prm [--repeat R] [--csv FILE]
 *
 * 1. Each change alone: the scene with stiffness warping (WCC at threshold inf, partial
 *    strategy), whose factor changes only with the changes, the solver choosing per change
 *    between updating its factor and recomputing columns (Solver/Change method = auto).
 *    At each step with a change: the elements cut or changed and vertices grasped or
 *    released, the columns it touched, the rank of the change in low-rank form, and the
 *    seconds of taking it from the factor of the step before, each way on a copy: warpchol's
 *    update, its partial refactorization, a full factorization, CHOLMOD's cholmod_updown
 *    of the same low-rank change on its simplicial LDL^T factor of the same matrix and
 *    permutation (the conversion not counted), and CHOLMOD analyzing anew and factoring
 *    (as SOFA does after a topological change). Each of warpchol's ways is told the
 *    changed columns, as the scene's model tells its solver (a complete listing: nothing
 *    else is compared), as cholmod_updown is given the change. Then what the run chose,
 *    what it predicted the update and the partial refactorization would cost, and the
 *    chosen method's time over the fastest of update, partial and full.
 * 2. Whole runs, seconds per step: the scene as its parameters say; the same without the
 *    changes; exact corotation refactored every step by warpchol and by CHOLMOD (which
 *    analyzes anew after each cut); the stale rest factor as CG's preconditioner (SOFA's
 *    warp preconditioner, to the scene's CG tolerance) with its iterations per step
 *    before the first change and after the last.
 * Output is switched off; the CSV (default output/SCENE/surgery.csv) has the first table.
 */

#include <warpchol/app/command_line.h>
#include <warpchol/app/output.h>
#include <warpchol/app/parameters.h>
#include <warpchol/app/scene.h>
#include <warpchol/backends/cholmod_reference.h>
#include <warpchol/backends/linear_solver.h>
#include <warpchol/base/atomic_file.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/cholesky/blas.h>
#include <warpchol/cholesky/low_rank_change.h>
#include <warpchol/cholesky/ordering.h>
#include <warpchol/reports/machine.h>
#include <warpchol/sparse/residual.h>

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

  /** The least of @p repeat runs of @p action, which returns the seconds it timed. */
  double best_of(const unsigned int repeat, const std::function<double()> &action)
  {
    double best = std::numeric_limits<double>::infinity();
    for (unsigned int r = 0; r < repeat; ++r)
      best = std::min(best, action());
    return best;
  }

  /** What one change step cost, each way. */
  struct ChangeRow
  {
    unsigned int step = 0;
    std::string  what;
    double       columns_pct = 0;
    Index        rank        = 0;
    double       update = 0, partial = 0, full = 0, cholmod_updown = 0, cholmod_anew = 0;
    /** What the run chose, and what it predicted the update and the partial refactorization would cost. */
    std::string  chosen;
    double       predicted_update = -1, predicted_partial = -1;

    double chosen_seconds() const
    {
      return chosen == "update" ? update : chosen == "partial" ? partial : full;
    }
    double fastest() const
    {
      return std::min({update, partial, full});
    }
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

  /**
   * The change from @p before to @p after (lower triangles, the user's numbering) in the
   * permuted numbering of @p solver, in low-rank form.
   */
  cholesky::LowRankChange change_between(const sparse::CSCMatrix &before, const sparse::CSCMatrix &after,
                                         const cholesky::SparseCholesky &solver)
  {
    const std::vector<Index> inverse = cholesky::invert_permutation(solver.permutation());
    std::vector<cholesky::PermutedMatrix::Change> changes;
    for (Index j = 0; j < after.n_cols; ++j)
      for (Index k = after.column_start[j]; k < after.column_start[j + 1]; ++k)
        if (after.values[k] != before.values[k])
          {
            const Index i = inverse[after.row_index[k]], column = inverse[j];
            changes.push_back({std::max(i, column), std::min(i, column), after.values[k] - before.values[k]});
          }
    return cholesky::low_rank_form(after.n_cols, changes);
  }

  /** CHOLMOD's update and downdate of @p change (one call each sign), on its LDL^T factor of @p before. */
  double cholmod_updown_seconds(const sparse::CSCMatrix &before, const cholesky::LowRankChange &change,
                                const cholesky::SparseCholesky &solver, const unsigned int repeat)
  {
    sparse::CSCMatrix part[2];
    for (int sign = 0; sign < 2; ++sign)
      {
        part[sign] = sparse::CSCMatrix::zero(change.c.n_rows, 0);
        for (Index t = 0; t < change.c.n_cols; ++t)
          if ((change.signs[t] > 0) == (sign == 0))
            {
              for (Index k = change.c.column_start[t]; k < change.c.column_start[t + 1]; ++k)
                {
                  part[sign].row_index.push_back(change.c.row_index[k]);
                  part[sign].values.push_back(change.c.values[k]);
                }
              part[sign].column_start.push_back(static_cast<Index>(part[sign].row_index.size()));
              ++part[sign].n_cols;
            }
      }
    double best = std::numeric_limits<double>::infinity();
    for (unsigned int r = 0; r < repeat; ++r)
      {
        cholesky::CholmodReference cholmod(false);
        cholmod.analyze(before, solver.permutation());
        cholmod.factorize(before);
        cholmod.convert_for_updates();
        double seconds = 0;
        for (int sign = 0; sign < 2; ++sign)
          if (part[sign].n_cols > 0)
            {
              cholmod.updown(sign == 0, part[sign]);
              seconds += cholmod.updown_seconds;
            }
        best = std::min(best, seconds);
      }
    return best;
  }

  std::vector<ChangeRow> change_costs(const app::AllParameters &scene_parameters, const unsigned int repeat)
  {
    app::AllParameters parameters      = scene_parameters;
    parameters.model.type              = fem::ModelType::warp_canceling;
    parameters.model.rerotation_threshold  = std::numeric_limits<double>::infinity();
    parameters.model.target_error      = 0;
    parameters.model.strategy.kind     = fem::StepStrategy::Kind::partial;
    parameters.solver.backend.backend  = backends::Backend::warpchol;
    parameters.solver.settings.change_method = cholesky::ChangeMethod::automatic;
    app::Scene             scene(parameters);
    std::vector<ChangeRow> rows;
    // The factor and the matrix of the step before, which each way starts from.
    cholesky::SparseCholesky before        = scene.model().solver();
    sparse::CSCMatrix        before_matrix = scene.model().system_matrix().lower();
    for (unsigned int step = 1; step <= parameters.time_stepping.n_steps; ++step)
      {
        fem::StepStatistics statistics;
        scene.integrator().advance(statistics);
        const auto              &model = scene.model();
        const sparse::CSCMatrix &after = model.system_matrix().lower();
        if (statistics.change_columns > 0)
          {
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
            row.chosen      = cholesky::to_string(statistics.factorization.method);
            row.predicted_update  = statistics.factorization.predicted_update_seconds;
            row.predicted_partial = statistics.factorization.predicted_partial_seconds;
            // Each way from a copy of the factor of the step before, assigned anew for each
            // repetition: the copy keeps its buffers from one to the next, warm as the
            // run's own solver's are, and the first, cold one is not the best.
            const std::vector<Index> listed = sparse::changed_columns(before_matrix, after);
            const auto from_before = [&](const cholesky::ChangeMethod method, const bool full) {
              cholesky::SparseCholesky solver = before;
              return best_of(repeat + 1, [&, method, full] {
                solver = before;
                solver.set_change_method(method);
                const Stopwatch stopwatch;
                if (full)
                  solver.factorize(after);
                else
                  solver.refactorize(after, listed, cholesky::Refresh::all, cholesky::ChangeListing::complete);
                return stopwatch.seconds();
              });
            };
            row.update  = from_before(cholesky::ChangeMethod::update, false);
            row.partial = from_before(cholesky::ChangeMethod::recompute, false);
            row.full    = from_before(cholesky::ChangeMethod::recompute, true);
            const cholesky::LowRankChange change = change_between(before_matrix, after, before);
            row.rank                             = change.c.n_cols;
            row.cholmod_updown                   = cholmod_updown_seconds(before_matrix, change, before, repeat);
            backends::Settings cholmod_settings;
            cholmod_settings.backend = backends::Backend::cholmod;
            auto cholmod             = backends::create_linear_solver(cholmod_settings, {});
            row.cholmod_anew         = best_of(repeat, [&] {
              const Stopwatch stopwatch;
              cholmod->topology_changed();
              cholmod->factorize(model.system_matrix().matrix(), model.system_matrix().csc());
              return stopwatch.seconds();
            });
            rows.push_back(row);
          }
        if (statistics.refactorized)
          {
            before        = model.solver();
            before_matrix = after;
          }
      }
    return rows;
  }

  /**
   * The scene as it says, beside the same without its changes, with its changes recomputed,
   * exact by warpchol and by CHOLMOD, and on the stale rest factor with CG: a table of
   * seconds a step and the ratios to the scene's own run.
   */
  void compare_whole_runs(const app::AllParameters &parameters)
  {
    std::vector<RunRow> runs;
    runs.push_back(run_scene("as the scene says (" + fem::to_string(parameters.model.type) + ", " +
                               fem::to_string(parameters.model.strategy.kind) + ")",
                             parameters));
    app::AllParameters unchanged = parameters;
    unchanged.cuts.clear();
    unchanged.grasps.clear();
    unchanged.material_changes.clear();
    runs.push_back(run_scene("the same without the changes", unchanged));
    app::AllParameters recomputing = parameters;
    recomputing.solver.settings.change_method = cholesky::ChangeMethod::recompute;
    runs.push_back(run_scene("the same, changes recomputed (no updates)", recomputing));
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
              << " % of the steps per second without them; " << format_number(runs[4].seconds_per_step / runs[0].seconds_per_step, 3)
              << "x faster than CHOLMOD refactoring every step, "
              << format_number(runs[5].seconds_per_step / runs[0].seconds_per_step, 3)
              << "x faster than the stale rest factor\n";
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

    std::cout << app::describe_machine() << "\n"
              << "scene " << parameters.scene_name() << ", " << parameters.time_stepping.n_steps << " steps, "
              << parameters.solver.settings.n_threads << " thread(s)\n\n"
              << "each change alone (stiffness warping: the factor changes only with the changes); seconds, best of "
              << options.repeat << "\n"
              << std::setw(5) << "step" << std::setw(24) << "change" << std::setw(9) << "columns%" << std::setw(6)
              << "rank" << std::setw(10) << "update" << std::setw(10) << "partial" << std::setw(10) << "full"
              << std::setw(12) << "CHOLMOD upd" << std::setw(12) << "CHOLMOD new" << std::setw(9) << "chosen"
              << std::setw(22) << "predicted upd / part" << std::setw(14) << "chosen/best" << "\n";
    const std::vector<ChangeRow> changes = change_costs(parameters, options.repeat);
    unsigned int                 within  = 0;
    double worst = 0, update_vs_cholmod = std::numeric_limits<double>::infinity();
    for (const auto &row : changes)
      {
        const double ratio = row.chosen_seconds() / row.fastest();
        within += ratio <= 1.2;
        worst             = std::max(worst, ratio);
        update_vs_cholmod = std::min(update_vs_cholmod, row.cholmod_updown / row.update);
        std::cout << std::setw(5) << row.step << std::setw(24) << row.what << std::setw(9)
                  << format_number(row.columns_pct, 3) << std::setw(6) << row.rank << std::setw(10)
                  << format_number(row.update, 3) << std::setw(10) << format_number(row.partial, 3) << std::setw(10)
                  << format_number(row.full, 3) << std::setw(12) << format_number(row.cholmod_updown, 3) << std::setw(12)
                  << format_number(row.cholmod_anew, 3) << std::setw(9) << row.chosen << std::setw(11)
                  << std::setw(12) << format_number(row.predicted_update, 3) << std::setw(10)
                  << format_number(row.predicted_partial, 3) << std::setw(14) << format_number(ratio, 3) << "\n";
      }
    std::cout << "steps whose chosen method is within 1.2x of the fastest of update, partial and full: " << within
              << " of " << changes.size() << " (worst " << format_number(worst, 3)
              << "x); update against CHOLMOD's updown at least " << format_number(update_vs_cholmod, 3) << "x\n\n";

    compare_whole_runs(parameters);

    write_file_atomically(csv_file, [&](std::ostream &out) {
      out << "step,change,columns_pct,rank,update_seconds,partial_seconds,full_seconds,cholmod_updown_seconds,"
             "cholmod_anew_seconds,chosen,predicted_update_seconds,predicted_partial_seconds\n";
      for (const auto &row : changes)
        out << row.step << "," << row.what << "," << row.columns_pct << "," << row.rank << "," << row.update << ","
            << row.partial << "," << row.full << "," << row.cholmod_updown << "," << row.cholmod_anew << ","
            << row.chosen << "," << row.predicted_update << "," << row.predicted_partial << "\n";
    });
    std::cout << "table: " << csv_file << std::endl;
  }
} // namespace

int main(int argc, char **argv)
{
  warpchol::cholesky::blas::restart_with_single_threaded_libraries(argv);
  return warpchol::app::run_program("warpchol-surgery", [&] { run(parse_command_line(argc, argv)); });
}
