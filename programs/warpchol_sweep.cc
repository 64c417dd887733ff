/**
 * warpchol-sweep: how partial refactorization pays against the changed fraction.
 *
 *   warpchol-sweep MATRIX.mtx [--ordering natural|amd|metis] [--method left|supernodal]
 *                             [--threads N] [--repeat R] [--seed S] [--csv]
 *
 * For growing sets of mesh vertices around a random one (all columns of each vertex
 * change, as a local mesh update changes them), change those columns keeping A SPD,
 * refactorize partially, and print per row: the vertices changed (% and count), the
 * columns, supernodes and flops recomputed (%), the partial time, the full factorization
 * time, CHOLMOD's full time (same permutation and BLAS, in this process), and the check
 * partial <= 1.2 x flop fraction x full + 1 ms. Times are the best of R runs.
 */

#include <warpchol/app/command_line.h>
#include <warpchol/backends/cholmod_reference.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/cholesky/blas.h>
#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/sparse/matrix_market.h>
#include <warpchol/sparse/spd_perturbation.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

namespace
{
  using namespace warpchol;

  const char *usage = "usage: warpchol-sweep MATRIX.mtx [--ordering natural|amd|metis] "
                      "[--method left|supernodal] [--threads N] [--repeat R] [--seed S] [--csv]";

  struct Options
  {
    std::string                        matrix_file;
    cholesky::SparseCholesky::Settings solver;
    int                                repeat = 3;
    std::uint64_t                      seed   = 1;
    bool                               csv    = false;
  };

  Options parse_command_line(const int argc, char **argv)
  {
    Options options;
    options.solver.method = cholesky::FactorizationMethod::supernodal;
    app::CommandLine command_line(argc, argv);
    while (command_line.has_next())
      {
        const std::string argument = command_line.next();
        if (command_line.read_solver_option(argument, options.solver))
          continue;
        if (argument == "--repeat")
          options.repeat = static_cast<int>(command_line.integer_of(argument, 1, 1000));
        else if (argument == "--seed")
          options.seed = static_cast<std::uint64_t>(command_line.integer_of(argument, 0, 1L << 62));
        else if (argument == "--csv")
          options.csv = true;
        else
          command_line.read_help_or_input_file(argument, usage, options.matrix_file);
      }
    if (options.matrix_file.empty())
      throw InputError(std::string("no matrix file given; ") + usage);
    if (options.solver.method == cholesky::FactorizationMethod::up_looking)
      throw InputError("--method up cannot refactorize partially");
    return options;
  }

  /** Best of @p repeat wall-clock times of @p action, which reports its own time. */
  template <typename Action>
  double best_time(const int repeat, const Action &action)
  {
    double best = 1e300;
    for (int r = 0; r < repeat; ++r)
      best = std::min(best, action());
    return best;
  }

  void run(const Options &options)
  {
    sparse::CSCMatrix        matrix = sparse::read_symmetric_matrix_market(options.matrix_file);
    cholesky::SparseCholesky solver(options.solver);
    solver.analyze(matrix);
    const double full_seconds = best_time(options.repeat, [&] {
      solver.factorize(matrix);
      return solver.statistics().factorize_seconds;
    });
    cholesky::CholmodReference cholmod(true);
    cholmod.analyze(matrix, solver.permutation());
    const double cholmod_seconds = best_time(options.repeat, [&] {
      cholmod.factorize(matrix);
      return cholmod.factorize_seconds;
    });

    const auto &stats      = solver.statistics();
    const int   block      = stats.vertex_block_size;
    const Index n_vertices = stats.n / block;
    std::cout << (options.csv ? "# " : "") << options.matrix_file << ": n=" << stats.n << " vertices=" << n_vertices
              << " (block " << block << ") nnz_l=" << stats.nnz_l
              << " ordering=" << cholesky::to_string(options.solver.ordering.method)
              << " method=" << cholesky::to_string(options.solver.method) << " threads=" << options.solver.n_threads
              << " supernodes=" << stats.n_supernodes << " full_s=" << format_number(full_seconds, 4)
              << " cholmod_s=" << format_number(cholmod_seconds, 4) << "\n";
    if (options.csv)
      std::cout << "vertices_pct,vertices,columns_pct,supernodes_pct,flops_pct,partial_s,full_s,cholmod_s,"
                   "bound_s,within_bound\n";
    else
      std::printf("%9s %8s %9s %11s %8s %10s %10s %10s %10s %6s\n", "vertices%", "vertices", "columns%",
                  "supernodes%", "flops%", "partial_s", "full_s", "cholmod_s", "bound_s", "ok");

    for (const double fraction : {0.0005, 0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0})
      {
        const Index count = std::max<Index>(1, static_cast<Index>(fraction * static_cast<double>(n_vertices)));
        const std::vector<Index> changed = sparse::local_vertex_columns(matrix, block, count, options.seed + count);
        sparse::perturb_columns_spd(matrix, changed, options.seed + count);
        const double partial_seconds = best_time(options.repeat, [&] {
          solver.refactorize(matrix, changed);
          return solver.statistics().refactorize_seconds;
        });
        const double columns_pct    = 100. * static_cast<double>(stats.columns_recomputed) / static_cast<double>(stats.n);
        const double supernodes_pct = stats.n_supernodes > 0 ? 100. * static_cast<double>(stats.supernodes_recomputed) /
                                                                 static_cast<double>(stats.n_supernodes) :
                                                               0.;
        const double flop_fraction = stats.flops_recomputed / stats.flops;
        const double bound         = 1.2 * flop_fraction * full_seconds + 1e-3;
        const bool   within        = partial_seconds <= bound;
        if (options.csv)
          std::cout << format_number(100. * count / n_vertices, 4) << ',' << count << ','
                    << format_number(columns_pct, 4) << ',' << format_number(supernodes_pct, 4) << ','
                    << format_number(100. * flop_fraction, 4) << ',' << format_number(partial_seconds, 4) << ','
                    << format_number(full_seconds, 4) << ',' << format_number(cholmod_seconds, 4) << ','
                    << format_number(bound, 4) << ',' << (within ? "yes" : "no") << "\n";
        else
          std::printf("%9.3f %8lld %9.2f %11.2f %8.2f %10.5f %10.5f %10.5f %10.5f %6s\n",
                      100. * static_cast<double>(count) / static_cast<double>(n_vertices),
                      static_cast<long long>(count), columns_pct, supernodes_pct, 100. * flop_fraction,
                      partial_seconds, full_seconds, cholmod_seconds, bound, within ? "yes" : "NO");
        std::fflush(stdout);
      }
  }
} // namespace

int main(int argc, char **argv)
{
  warpchol::cholesky::blas::restart_with_single_threaded_libraries(argv);
  return warpchol::app::run_program("warpchol-sweep", [&] { run(parse_command_line(argc, argv)); });
}
