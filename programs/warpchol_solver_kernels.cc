/**
 * warpchol-solver-kernels: the solver's kernels on every SIMD target this CPU runs, side by
 * side, on one matrix: what each target gains, measured in one run.
 *
 *   warpchol-solver-kernels MATRIX.mtx [--ranks 1,3,9,16,32,64] [--targets avx512,avx2,...]
 *                                      [--repeat R] [--seed S] [--only updates|solves|factorization]
 *
 * The matrix is factored once (supernodal, METIS, one thread); then, on each target forced
 * as WARPCHOL_SIMD_TARGET forces it, each kernel is timed, best of R (default 7):
 * - the rank-k update and downdate of the factor (a grasp-like change, as warpchol-factor
 *   --update-rank makes it: a penalty on the unknowns of the vertices around a random one);
 * - the preconditioner's solves with the 16-bit and 32-bit copies of the factor, and the
 *   double solve;
 * - the supernodal factorization (its dense kernels are BLAS's, whose own dispatch the
 *   target does not change: the row shows it).
 * CHOLMOD's cholmod_updown on its simplicial LDL^T factor of the same matrix and
 * permutation is timed beside the updates, and cholmod_solve on its supernodal factor beside
 * the double solve. Prints the machine, then a Markdown table: per kernel, ms per target,
 * the default target's time over the fastest's (marked "slow" past 1.15), and CHOLMOD's
 * time over the default's where CHOLMOD has the kernel.
 */

#include <warpchol/app/command_line.h>
#include <warpchol/backends/cholmod_reference.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/simd.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/cholesky/blas.h>
#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/reports/machine.h>
#include <warpchol/sparse/matrix_market.h>
#include <warpchol/sparse/spd_perturbation.h>

#include <algorithm>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>

using namespace warpchol;

namespace
{
  const char *usage = "usage: warpchol-solver-kernels MATRIX.mtx [--ranks K1,K2,...] [--targets T1,T2,...] "
                      "[--repeat R] [--seed S] [--only updates|solves|factorization]";

  /** Timed runs of a kernel in a row, after an untimed one, per repetition. */
  constexpr int runs_in_a_row = 3;

  struct Options
  {
    std::string              matrix_file;
    std::vector<Index>       ranks   = {1, 3, 9, 16, 32, 64};
    std::vector<std::string> targets = simd::available_targets();
    int                      repeat  = 7;
    std::uint64_t            seed    = 1;
    /** Which kernels to time (--only): empty for all, else "updates", "solves" or "factorization". */
    std::string              only;
  };

  std::vector<std::string> split_list(const std::string &text)
  {
    std::vector<std::string> items;
    std::istringstream       list(text);
    for (std::string item; std::getline(list, item, ',');)
      items.push_back(item);
    return items;
  }

  Options parse_command_line(const int argc, char **argv)
  {
    Options          options;
    app::CommandLine line(argc, argv);
    while (line.has_next())
      {
        const std::string argument = line.next();
        if (argument == "--ranks")
          {
            options.ranks.clear();
            for (const std::string &item : split_list(line.value_of(argument)))
              {
                char      *end  = nullptr;
                const long rank = std::strtol(item.c_str(), &end, 10);
                if (item.empty() || *end != '\0' || rank < 1 || rank > 100000)
                  throw InputError("--ranks: '" + item + "' is not a rank in [1, 100000]");
                options.ranks.push_back(rank);
              }
          }
        else if (argument == "--targets")
          options.targets = split_list(line.value_of(argument));
        else if (argument == "--repeat")
          options.repeat = static_cast<int>(line.integer_of(argument, 1, 100000));
        else if (argument == "--only")
          {
            options.only = line.value_of(argument);
            if (options.only != "updates" && options.only != "solves" && options.only != "factorization")
              throw InputError("--only: expected updates, solves or factorization, got '" + options.only + "'");
          }
        else if (argument == "--seed")
          options.seed = static_cast<std::uint64_t>(line.integer_of(argument, 0, 1L << 62));
        else
          line.read_help_or_input_file(argument, usage, options.matrix_file);
      }
    if (options.matrix_file.empty())
      throw InputError(std::string("no matrix file given; ") + usage);
    for (const std::string &target : options.targets)
      try
        {
          simd::use_target(target);
        }
      catch (const std::invalid_argument &error)
        {
          throw InputError(std::string("--targets: ") + error.what());
        }
    return options;
  }

  double seconds_of(const std::function<void()> &kernel)
  {
    const Stopwatch stopwatch;
    kernel();
    return stopwatch.seconds();
  }

  /**
   * What one measurement times: one or more kernels (an update and the downdate that undoes
   * it), each a row of the table, and their peer's times if they have one (CHOLMOD).
   */
  struct Measurement
  {
    std::vector<std::string>                  kernels;
    /** Runs the kernels once on the current target: their seconds. */
    std::function<std::vector<double>()>      run;
    /** Runs the peer's kernels once (empty: none). */
    std::function<std::vector<double>()>      run_peer;
    /** Best seconds per kernel and target, and the peer's. */
    std::vector<std::vector<double>>          best;
    std::vector<double>                       peer_best;
    /** The family whose default target the kernels run unless one is forced. */
    simd::Family                              family = simd::Family::element;
  };

  void keep_best(std::vector<double> &best, const std::vector<double> &seconds)
  {
    if (best.empty())
      best.assign(seconds.size(), std::numeric_limits<double>::infinity());
    for (std::size_t k = 0; k < seconds.size(); ++k)
      best[k] = std::min(best[k], seconds[k]);
  }

  /**
   * Every kernel on every target and its peer in turn, R times: a slow stretch of the
   * machine falls on all of them alike, and the ratios are of one run. Each is run once
   * untimed first, so that each is timed with its own data in the caches, not the other's,
   * then a few times in a row.
   */
  void time_on_every_target(std::vector<Measurement> &measurements, const Options &options)
  {
    for (Measurement &measurement : measurements)
      measurement.best.resize(options.targets.size());
    for (int r = 0; r < options.repeat; ++r)
      for (Measurement &measurement : measurements)
        {
          if (measurement.run_peer)
            {
              measurement.run_peer();
              for (int k = 0; k < runs_in_a_row; ++k)
                keep_best(measurement.peer_best, measurement.run_peer());
            }
          for (std::size_t t = 0; t < options.targets.size(); ++t)
            {
              simd::use_target(options.targets[t]);
              measurement.run();
              for (int k = 0; k < runs_in_a_row; ++k)
                keep_best(measurement.best[t], measurement.run());
            }
        }
  }

  /** The table: per kernel, its best milliseconds per target, default / fastest and its peer's. */
  void print_table(const std::vector<Measurement> &measurements, const Options &options, const Index n,
                   const std::string &default_target, const std::string &update_target)
  {
    const auto column_of = [&](const std::string &target) -> long {
      const auto found = std::find(options.targets.begin(), options.targets.end(), target);
      return found == options.targets.end() ? -1 : found - options.targets.begin();
    };
    std::cout << options.matrix_file << ": n " << n << ", one thread, ms (best of " << options.repeat << " x "
              << runs_in_a_row << "); default target " << default_target << ", updates " << update_target
              << "\n\n| kernel |";
    for (const std::string &target : options.targets)
      std::cout << " " << target << " |";
    std::cout << " default / fastest | CHOLMOD | CHOLMOD / default |\n|---|";
    for (std::size_t k = 0; k < options.targets.size(); ++k)
      std::cout << "---:|";
    std::cout << "---:|---:|---:|\n";
    for (const Measurement &measurement : measurements)
      for (std::size_t k = 0; k < measurement.kernels.size(); ++k)
        {
          std::cout << "| " << measurement.kernels[k] << " |";
          double fastest = std::numeric_limits<double>::infinity();
          for (const std::vector<double> &best : measurement.best)
            {
              std::cout << " " << format_number(1e3 * best[k], 3) << " |";
              fastest = std::min(fastest, best[k]);
            }
          const long   default_column =
            column_of(measurement.family == simd::Family::update ? update_target : default_target);
          const bool   has_default     = default_column >= 0;
          const double default_seconds = has_default ? measurement.best[default_column][k] : 0.;
          if (has_default)
            {
              const double ratio = default_seconds / fastest;
              std::cout << " " << format_number(ratio, 3) << (ratio > app::slow_default_ratio ? " slow" : "") << " |";
            }
          else
            std::cout << " - |";
          if (!measurement.peer_best.empty())
            std::cout << " " << format_number(1e3 * measurement.peer_best[k], 3) << " | "
                      << (has_default ? format_number(measurement.peer_best[k] / default_seconds, 3) : "-") << " |\n";
          else
            std::cout << " | |\n";
        }
  }

  void run(const Options &options)
  {
    simd::use_target("default");
    const std::string default_target = simd::current_target(), update_target = simd::current_target(simd::Family::update);
    std::cout << app::describe_machine() << "\n";

    const sparse::CSCMatrix            matrix = sparse::read_symmetric_matrix_market(options.matrix_file);
    cholesky::SparseCholesky::Settings settings;
    settings.method          = cholesky::FactorizationMethod::supernodal;
    settings.ordering.method = cholesky::OrderingMethod::metis;
    settings.change_method   = cholesky::ChangeMethod::update;
    const auto solver_with = [&](const cholesky::PreconditionerPrecision precision) {
      cholesky::SparseCholesky::Settings with = settings;
      with.preconditioner_precision           = precision;
      cholesky::SparseCholesky solver(with);
      solver.analyze(matrix);
      solver.factorize(matrix);
      return solver;
    };
    cholesky::SparseCholesky solver = solver_with(cholesky::PreconditionerPrecision::full);
    cholesky::SparseCholesky half   = solver_with(cholesky::PreconditionerPrecision::half);
    cholesky::SparseCholesky single = solver_with(cholesky::PreconditionerPrecision::single);
    cholesky::CholmodReference cholmod(false);
    cholmod.analyze(matrix, solver.permutation());
    cholmod.factorize(matrix);
    cholmod.convert_for_updates();

    const Index                    n     = matrix.n_cols;
    const int                      block = n % 3 == 0 ? 3 : 1;
    const std::vector<Index>       inverse = cholesky::invert_permutation(solver.permutation());
    std::vector<sparse::CSCMatrix> changes, permuted_changes;
    const auto timed = [&](const std::string &family) { return options.only.empty() || options.only == family; };
    for (const Index rank : timed("updates") ? options.ranks : std::vector<Index>{})
      {
        std::vector<Index> columns =
          sparse::local_vertex_columns(matrix, block, (rank + block - 1) / block, options.seed);
        columns.resize(std::min<std::size_t>(columns.size(), rank));
        changes.push_back(sparse::penalty_columns(matrix, columns, 100.));
        permuted_changes.push_back(changes.back());
        for (Index &row : permuted_changes.back().row_index)
          row = inverse[row];
      }
    const std::vector<double> ones(n, 1.);
    std::vector<double>       b(n), x(n);
    matrix.vmult(ones.data(), b.data());

    std::vector<Measurement> measurements;
    for (std::size_t k = 0; k < changes.size(); ++k)
      {
        const std::string rank = std::to_string(changes[k].n_cols);
        measurements.push_back({{"update, rank " + rank, "downdate, rank " + rank},
                                [&, k] {
                                  solver.update(changes[k]);
                                  const double update = solver.statistics().refactorize_seconds;
                                  solver.downdate(changes[k]);
                                  return std::vector<double>{update, solver.statistics().refactorize_seconds};
                                },
                                [&, k] {
                                  cholmod.updown(true, permuted_changes[k]);
                                  const double update = cholmod.updown_seconds;
                                  cholmod.updown(false, permuted_changes[k]);
                                  return std::vector<double>{update, cholmod.updown_seconds};
                                },
                                {},
                                {},
                                simd::Family::update});
      }
    const auto one_kernel = [](const std::function<void()> &kernel) {
      return [kernel] { return std::vector<double>{seconds_of(kernel)}; };
    };
    cholesky::CholmodReference cholmod_supernodal(true);
    if (timed("solves"))
      {
        measurements.push_back({{"solve, 16-bit factor (preconditioner)"},
                                one_kernel([&] { half.apply_preconditioner(b.data(), x.data()); }), {}, {}, {}});
        measurements.push_back({{"solve, 32-bit factor (preconditioner)"},
                                one_kernel([&] { single.apply_preconditioner(b.data(), x.data()); }), {}, {}, {}});
        // CHOLMOD's supernodal solve (cholmod_solve) with its own factor of the same
        // matrix and permutation.
        cholmod_supernodal.analyze(matrix, solver.permutation());
        cholmod_supernodal.factorize(matrix);
        measurements.push_back({{"solve, double factor"},
                                one_kernel([&] { solver.solve(b.data(), x.data(), 1); }),
                                one_kernel([&] { x = cholmod_supernodal.solve(b); }),
                                {},
                                {}});
      }
    if (timed("factorization"))
      measurements.push_back({{"supernodal factorization (BLAS)"},
                              [&] {
                                solver.factorize(matrix);
                                return std::vector<double>{solver.statistics().factorize_seconds};
                              },
                              {},
                              {},
                              {}});

    time_on_every_target(measurements, options);
    print_table(measurements, options, n, default_target, update_target);
  }
} // namespace

int main(int argc, char **argv)
{
  cholesky::blas::restart_with_single_threaded_libraries(argv);
  return app::run_program("warpchol-solver-kernels", [&] { run(parse_command_line(argc, argv)); });
}
