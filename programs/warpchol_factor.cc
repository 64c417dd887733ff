/**
 * warpchol-factor: factor a symmetric positive definite Matrix Market file, refactor it
 * after changing a random fraction of its columns, solve, and print one line of
 * key=value fields that scripts can read.
 *
 *   warpchol-factor MATRIX.mtx [--ordering natural|amd|metis] [--method left|up|supernodal]
 *                              [--supernodal on|off] [--threads N] [--changed-fraction P]
 *                              [--seed S] [--repeat R] [--max-seconds S] [--compare cholmod]
 *                              [--relaxation off|N0,N1,N2,Z0,Z1,Z2] [--update-rank K]
 *                              [--change-method auto|flops|recompute|update]
 *
 * Times are the best of R runs (the machine is shared and noisy), the factorization's also
 * their median (factor_median_s). --max-seconds S stops the repeats of the factorization
 * once they have taken S seconds in all (at least one runs; repeats= says how many did):
 * a natural ordering on a 3D mesh takes a minute per factorization column by column.
 * With --compare cholmod, CHOLMOD's supernodal factorization runs in the same process on
 * the same matrix with the same permutation and BLAS, alternating with ours, and the
 * ratios ours/CHOLMOD are printed. With --changed-fraction 0 nothing changes and no
 * refactorization runs (refactor_s=0).
 *
 * With --update-rank K, a grasp-like change of rank K (a penalty of 100 A(j,j) on the
 * diagonal of the K dofs of the vertices around a random one, C = sqrt(100 A(j,j)) e_j) is
 * taken, on the factor of the unchanged matrix, four ways: warpchol's update (and the
 * downdate that undoes it), warpchol's partial refactorization of the same columns, a full
 * factorization, and CHOLMOD's cholmod_updown on its simplicial LDL^T factor of the same
 * matrix with the same permutation (the conversion from its supernodal factor not counted:
 * updates need it); the ways in turn within each of R repeats, each twice in a row, best of
 * all its runs each, with the flops and the relative residual of a solve with A + C C^T
 * (update_*, partial_*, cholmod_updown_*).
 */

#include <warpchol/app/command_line.h>
#include <warpchol/backends/cholmod_reference.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/cholesky/blas.h>
#include <warpchol/cholesky/ordering.h>
#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/reports/machine.h>
#include <warpchol/sparse/matrix_market.h>
#include <warpchol/sparse/residual.h>
#include <warpchol/sparse/spd_perturbation.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace
{
  using namespace warpchol;

  struct Options
  {
    std::string                              matrix_file;
    cholesky::SparseCholesky::Settings       solver;
    double                                   changed_fraction = 0.1;
    std::uint64_t                            seed             = 1;
    int                                      repeat           = 1;
    double                                   max_seconds      = 0;
    bool                                     compare_cholmod  = false;
    Index                                    update_rank      = 0;
  };

  const char *usage = "usage: warpchol-factor MATRIX.mtx [--ordering natural|amd|metis] "
                      "[--method left|up|supernodal] [--supernodal on|off] [--threads N] "
                      "[--changed-fraction P] [--seed S] [--repeat R] [--max-seconds S] "
                      "[--compare cholmod] "
                      "[--relaxation off|N0,N1,N2,Z0,Z1,Z2] [--update-rank K] "
                      "[--change-method auto|flops|recompute|update]";

  Options parse_command_line(const int argc, char **argv)
  {
    Options          options;
    app::CommandLine command_line(argc, argv);
    while (command_line.has_next())
      {
        const std::string argument = command_line.next();
        if (command_line.read_solver_option(argument, options.solver))
          continue;
        if (argument == "--changed-fraction")
          {
            options.changed_fraction = command_line.number_of(argument);
            if (options.changed_fraction < 0 || options.changed_fraction > 1)
              throw InputError("--changed-fraction must lie in [0, 1], got " + format_number(options.changed_fraction));
          }
        else if (argument == "--seed")
          options.seed = static_cast<std::uint64_t>(command_line.integer_of(argument, 0, 1L << 62));
        else if (argument == "--update-rank")
          options.update_rank = command_line.integer_of(argument, 1, 100000);
        else if (argument == "--repeat")
          options.repeat = static_cast<int>(command_line.integer_of(argument, 1, 1000));
        else if (argument == "--max-seconds")
          {
            options.max_seconds = command_line.number_of(argument);
            if (!(options.max_seconds > 0))
              throw InputError("--max-seconds must be > 0, got " + format_number(options.max_seconds));
          }
        else if (argument == "--compare")
          {
            const std::string peer = command_line.value_of(argument);
            if (peer != "cholmod")
              throw InputError("--compare: only 'cholmod' is supported, got '" + peer + "'");
            options.compare_cholmod = true;
          }
        else
          command_line.read_help_or_input_file(argument, usage, options.matrix_file);
      }
    if (options.matrix_file.empty())
      throw InputError(std::string("no matrix file given; ") + usage);
    return options;
  }

  /** The median of @p times (not empty). */
  double median(std::vector<double> times)
  {
    std::sort(times.begin(), times.end());
    const std::size_t middle = times.size() / 2;
    return times.size() % 2 == 1 ? times[middle] : 0.5 * (times[middle - 1] + times[middle]);
  }

  /**
   * The grasp-like change of --update-rank taken four ways on the factor of @p matrix
   * (which @p solver holds): warpchol's update and downdate, its partial refactorization,
   * CHOLMOD's updown. Prints the fields.
   */
  void compare_updates(const Options &options, const sparse::CSCMatrix &matrix, cholesky::SparseCholesky &solver)
  {
    const Index              n       = matrix.n_cols;
    const int                block   = n % 3 == 0 ? 3 : 1;
    std::vector<Index>       columns = sparse::local_vertex_columns(matrix, block, (options.update_rank + block - 1) / block,
                                                                    options.seed);
    columns.resize(std::min<std::size_t>(columns.size(), options.update_rank));
    const sparse::CSCMatrix c       = sparse::penalty_columns(matrix, columns, 100.);
    sparse::CSCMatrix       changed = matrix;
    sparse::add_outer_products(changed, c, 1.);
    const std::vector<double> ones(n, 1.);
    std::vector<double>       b(n), x;
    changed.vmult(ones.data(), b.data());

    // warpchol's partial refactorization of the same columns (a solver that never updates).
    cholesky::SparseCholesky::Settings recompute_settings = options.solver;
    recompute_settings.change_method                      = cholesky::ChangeMethod::recompute;
    cholesky::SparseCholesky recompute(recompute_settings);
    recompute.analyze(matrix);
    recompute.factorize(matrix);

    // CHOLMOD: its simplicial LDL^T factor of the same matrix, same permutation, updown.
    cholesky::CholmodReference cholmod(false);
    cholmod.analyze(matrix, solver.permutation());
    cholmod.factorize(matrix);
    cholmod.convert_for_updates();
    const std::vector<Index> inverse = cholesky::invert_permutation(solver.permutation());
    sparse::CSCMatrix        permuted_c = c;
    for (Index &row : permuted_c.row_index)
      row = inverse[row];

    // The three ways in turn within each repeat, best of the repeats each: a burst of
    // load on a shared machine then slows one repeat of all three, not all repeats of one.
    // Each way runs twice in a row, so that its second run finds its own factor in cache
    // as consecutive repeats would.
    double update_seconds = 1e300, downdate_seconds = 1e300, update_flops = 0;
    double partial_seconds = 1e300, partial_flops = 0;
    double cholmod_update_seconds = 1e300, cholmod_downdate_seconds = 1e300;
    std::vector<double> cholmod_x;
    constexpr int       runs_in_a_row = 2;
    for (int r = 0; r < options.repeat; ++r)
      {
        const bool last = r + 1 == options.repeat;
        // warpchol: update, then the downdate that brings the factor back.
        for (int k = 0; k < runs_in_a_row; ++k)
          {
            solver.update(c);
            update_seconds = std::min(update_seconds, solver.statistics().refactorize_seconds);
            update_flops   = solver.statistics().flops_recomputed;
            if (last)
              solver.solve(b, x);
            solver.downdate(c);
            downdate_seconds = std::min(downdate_seconds, solver.statistics().refactorize_seconds);
          }
        for (int k = 0; k < runs_in_a_row; ++k)
          {
            recompute.refactorize(changed, columns);
            partial_seconds = std::min(partial_seconds, recompute.statistics().refactorize_seconds);
            partial_flops   = recompute.statistics().flops_recomputed;
            recompute.refactorize(matrix, columns);
          }
        for (int k = 0; k < runs_in_a_row; ++k)
          {
            cholmod.updown(true, permuted_c);
            cholmod_update_seconds = std::min(cholmod_update_seconds, cholmod.updown_seconds);
            if (last)
              cholmod_x = cholmod.solve(b);
            cholmod.updown(false, permuted_c);
            cholmod_downdate_seconds = std::min(cholmod_downdate_seconds, cholmod.updown_seconds);
          }
      }
    const double update_residual = sparse::relative_residual(changed, x, b);
    const cholesky::ModificationPlan plan = cholesky::plan_modification(solver.supernodal_symbolic(), [&] {
      std::vector<Index> first_rows;
      for (const Index j : columns)
        first_rows.push_back(std::find(solver.permutation().begin(), solver.permutation().end(), j) -
                             solver.permutation().begin());
      return first_rows;
    }());

    std::cout << " update_rank=" << c.n_cols << " update_s=" << format_number(update_seconds, 4)
              << " downdate_s=" << format_number(downdate_seconds, 4)
              << " update_flops=" << format_number(update_flops, 4)
              << " update_entries=" << plan.n_entries
              << " update_gflops=" << format_number(update_flops / update_seconds * 1e-9, 3)
              << " update_residual=" << format_number(update_residual, 3)
              << " partial_s=" << format_number(partial_seconds, 4)
              << " partial_flops=" << format_number(partial_flops, 4)
              << " cholmod_updown_s=" << format_number(cholmod_update_seconds, 4)
              << " cholmod_downdate_s=" << format_number(cholmod_downdate_seconds, 4)
              << " cholmod_update_residual=" << format_number(sparse::relative_residual(changed, cholmod_x, b), 3)
              << " update_vs_cholmod=" << format_number(cholmod_update_seconds / update_seconds, 3)
              << " downdate_vs_cholmod=" << format_number(cholmod_downdate_seconds / downdate_seconds, 3)
              << " update_vs_partial=" << format_number(partial_seconds / update_seconds, 3);
  }

  /** What compare_updates() prints, as a string: the fields that end the output line. */
  std::string update_fields_of(const Options &options, const sparse::CSCMatrix &matrix,
                               cholesky::SparseCholesky &solver)
  {
    std::ostringstream    fields;
    std::streambuf *const line = std::cout.rdbuf(fields.rdbuf());
    try
      {
        compare_updates(options, matrix, solver);
      }
    catch (...)
      {
        std::cout.rdbuf(line);
        throw;
      }
    std::cout.rdbuf(line);
    return fields.str();
  }

  void run(const Options &options)
  {
    sparse::CSCMatrix        matrix = sparse::read_symmetric_matrix_market(options.matrix_file);
    cholesky::SparseCholesky solver(options.solver);
    solver.analyze(matrix);
    // With --compare cholmod, CHOLMOD's supernodal factorization of the same matrix with
    // the same permutation alternates with ours, so that both see the same machine load.
    std::unique_ptr<cholesky::CholmodReference> cholmod;
    if (options.compare_cholmod)
      {
        cholmod = std::make_unique<cholesky::CholmodReference>(true);
        cholmod->analyze(matrix, solver.permutation());
      }
    std::vector<double> factor_times, cholmod_times;
    double              spent_seconds = 0;
    for (int r = 0; r < options.repeat; ++r)
      {
        if (r > 0 && options.max_seconds > 0 && spent_seconds >= options.max_seconds)
          break;
        solver.factorize(matrix);
        factor_times.push_back(solver.statistics().factorize_seconds);
        spent_seconds += factor_times.back();
        if (cholmod)
          {
            cholmod->factorize(matrix);
            cholmod_times.push_back(cholmod->factorize_seconds);
            spent_seconds += cholmod_times.back();
          }
      }
    const double factor_seconds = *std::min_element(factor_times.begin(), factor_times.end());
    // The update fields go at the end of the line; measured on the unchanged matrix.
    const std::string update_fields = options.update_rank > 0 ? update_fields_of(options, matrix, solver) : "";

    // Change a random set of columns (and rows), keeping A symmetric positive definite.
    const auto n_changed = static_cast<Index>(std::llround(options.changed_fraction * matrix.n_cols));
    const std::vector<Index> changed = sparse::random_columns(matrix.n_cols, n_changed, options.seed);
    sparse::perturb_columns_spd(matrix, changed, options.seed);
    // Nothing changed, nothing to refactor (the up-looking method would factor it all again).
    double refactor_seconds = changed.empty() ? 0. : 1e300;
    for (int r = 0; r < options.repeat && !changed.empty(); ++r)
      {
        solver.refactorize(matrix, changed);
        refactor_seconds = std::min(refactor_seconds, solver.statistics().refactorize_seconds);
      }

    // b = A x_true with x_true = 1, solve with the updated factor.
    const std::vector<double> ones(matrix.n_cols, 1.);
    std::vector<double>       b(matrix.n_cols), x;
    matrix.vmult(ones.data(), b.data());
    const Stopwatch solve_stopwatch;
    solver.solve(b, x);
    const double solve_seconds = solve_stopwatch.seconds();

    const auto  &stats = solver.statistics();
    const double n     = static_cast<double>(stats.n);
    std::cout << "n=" << stats.n << " nnz_a=" << stats.nnz_a << " nnz_l=" << stats.nnz_l
              << " fill=" << format_number(stats.fill(), 6)
              << " fill_full=" << format_number(static_cast<double>(stats.nnz_l) / (2. * stats.nnz_a - n), 6)
              << " flops=" << format_number(stats.flops, 6)
              << " exact_flops=" << format_number(stats.exact_flops, 6)
              << " ordering=" << cholesky::to_string(options.solver.ordering.method)
              << " method=" << cholesky::to_string(options.solver.method)
              << " threads=" << options.solver.n_threads
              << " vertex_block=" << stats.vertex_block_size
              << " supernodes=" << stats.n_supernodes
              << " analyze_s=" << format_number(stats.analyze_seconds, 4)
              << " repeats=" << factor_times.size()
              << " factor_s=" << format_number(factor_seconds, 4)
              << " factor_median_s=" << format_number(median(factor_times), 4)
              << " refactor_s=" << format_number(refactor_seconds, 4)
              << " solve_s=" << format_number(solve_seconds, 4)
              << " changed_cols=" << format_number(static_cast<double>(changed.size()) / n, 4)
              << " cols_recomputed=" << format_number(static_cast<double>(stats.columns_recomputed) / n, 4)
              << " supernodes_recomputed="
              << format_number(stats.n_supernodes > 0 ? static_cast<double>(stats.supernodes_recomputed) / stats.n_supernodes : 0., 4)
              << " flops_recomputed=" << format_number(stats.flops_recomputed / stats.flops, 4)
              << " factor_bytes=" << stats.factor_bytes
              << " residual=" << format_number(sparse::relative_residual(matrix, x, b), 3)
              << " backward_error=" << format_number(sparse::backward_error(matrix, x, b), 3);

    if (cholmod)
      {
        const double cholmod_seconds = *std::min_element(cholmod_times.begin(), cholmod_times.end());
        std::cout << " cholmod_factor_s=" << format_number(cholmod_seconds, 4)
                  << " cholmod_median_s=" << format_number(median(cholmod_times), 4)
                  << " factor_ratio=" << format_number(factor_seconds / cholmod_seconds, 3)
                  << " cholmod_bytes=" << cholmod->factor_bytes()
                  << " memory_ratio=" << format_number(static_cast<double>(stats.factor_bytes) / cholmod->factor_bytes(), 3);
      }
    // A benchmark's figures are read against the machine's ceilings.
    if (options.update_rank > 0 || options.compare_cholmod)
      std::cout << " simd=" << app::simd_target() << " update_simd=" << app::simd_target(warpchol::simd::Family::update)
                << " dgemm_gflops=" << format_number(cholesky::blas::measure_dgemm_gflops(), 3)
                << " blas_kernels=" << cholesky::blas::kernel_name()
                << " read_gbs=" << format_number(app::measure_read_bandwidth(), 3);
    std::cout << update_fields << "\n";
  }
} // namespace

int main(int argc, char **argv)
{
  warpchol::cholesky::blas::restart_with_single_threaded_libraries(argv);
  return warpchol::app::run_program("warpchol-factor", [&] { run(parse_command_line(argc, argv)); });
}
