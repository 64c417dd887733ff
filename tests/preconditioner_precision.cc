// The preconditioner's copy of the factor in single and half precision (bcsstk16, whose
// factor's entries, 1e-3 to 1e5, lie partly outside half's range unless scaled):
// apply_preconditioner() against the double solve, CG preconditioned by it (iterations to
// 1e-10), the bits on 1 and 2 threads, A scaled by 2^-80 and 2^80 (the column scales take
// it: the result scales by 2^80 bit for bit) and by 1e30, the copy following a
// refactorization of changed columns and an update (errors within 2x of a fresh factor's;
// the copy rounded on first read as when asked beforehand),
// every SIMD target against the baseline's, and the bytes each precision keeps.

#include <warpchol/base/simd.h>
#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/sparse/matrix_market.h>
#include <warpchol/sparse/spd_perturbation.h>

#include <cmath>

#include "modification_tests.h"
#include "tests.h"

using namespace warpchol;
using cholesky::PreconditionerPrecision;

namespace
{
  double norm(const std::vector<double> &v)
  {
    double sum = 0;
    for (const double x : v)
      sum += x * x;
    return std::sqrt(sum);
  }

  /** ||M^-1 b - A^-1 b|| / ||A^-1 b|| with M the preconditioner's copy of the factor. */
  double preconditioner_error(const cholesky::SparseCholesky &solver, const std::vector<double> &b)
  {
    std::vector<double> exact, approximate(b.size());
    solver.solve(b, exact);
    solver.apply_preconditioner(b.data(), approximate.data());
    for (std::size_t i = 0; i < b.size(); ++i)
      approximate[i] -= exact[i];
    return norm(approximate) / norm(exact);
  }

  /** Iterations of CG preconditioned by apply_preconditioner() to ||A x - b|| <= 1e-10 ||b||. */
  int cg_iterations(const cholesky::SparseCholesky &solver, const sparse::CSCMatrix &matrix,
                    const std::vector<double> &b)
  {
    const std::size_t   n = b.size();
    std::vector<double> x(n, 0.), r = b, z(n), p(n), q(n);
    solver.apply_preconditioner(r.data(), z.data());
    p             = z;
    double rz     = 0;
    for (std::size_t i = 0; i < n; ++i)
      rz += r[i] * z[i];
    for (int iteration = 1; iteration <= 100; ++iteration)
      {
        matrix.vmult(p.data(), q.data());
        double pq = 0;
        for (std::size_t i = 0; i < n; ++i)
          pq += p[i] * q[i];
        const double alpha = rz / pq;
        for (std::size_t i = 0; i < n; ++i)
          {
            x[i] += alpha * p[i];
            r[i] -= alpha * q[i];
          }
        if (norm(r) <= 1e-10 * norm(b))
          return iteration;
        solver.apply_preconditioner(r.data(), z.data());
        double rz_next = 0;
        for (std::size_t i = 0; i < n; ++i)
          rz_next += r[i] * z[i];
        for (std::size_t i = 0; i < n; ++i)
          p[i] = z[i] + rz_next / rz * p[i];
        rz = rz_next;
      }
    return 1000;
  }

  cholesky::SparseCholesky factored(const sparse::CSCMatrix &matrix, const PreconditionerPrecision precision,
                                    const unsigned int n_threads = 1)
  {
    cholesky::SparseCholesky::Settings settings = tests::supernodal_metis();
    settings.preconditioner_precision           = precision;
    settings.n_threads                          = n_threads;
    cholesky::SparseCholesky solver(settings);
    solver.analyze(matrix);
    solver.factorize(matrix);
    return solver;
  }

  sparse::CSCMatrix scaled(sparse::CSCMatrix matrix, const double factor)
  {
    for (double &value : matrix.values)
      value *= factor;
    return matrix;
  }
} // namespace

// The checks in the order of the .output file, each a few lines: a list, kept in one place.
int main()
{
  const sparse::CSCMatrix   matrix = sparse::read_matrix_market(tests::data_file("bcsstk16.mtx"));
  const std::vector<double> b      = tests::right_hand_side_of_random_solution(matrix, 5);

  const cholesky::SparseCholesky full   = factored(matrix, PreconditionerPrecision::full);
  const cholesky::SparseCholesky single = factored(matrix, PreconditionerPrecision::single);
  const cholesky::SparseCholesky half   = factored(matrix, PreconditionerPrecision::half);

  std::cout << "against the double solve, ||M^-1 b - A^-1 b|| / ||A^-1 b||:" << std::endl;
  tests::check_below("  full", preconditioner_error(full, b), 1e-14);
  tests::check_below("  single", preconditioner_error(single, b), 2e-5);
  const double half_error = preconditioner_error(half, b);
  tests::check_below("  half", half_error, 1e-2);
  tests::check("  half above single's rounding (it is a coarser copy)", half_error > 1e-5);

  std::cout << "CG preconditioned by each, iterations to 1e-10:" << std::endl;
  tests::check_below("  single", cg_iterations(single, matrix, b), 3);
  tests::check_below("  half", cg_iterations(half, matrix, b), 6);

  std::cout << "threads:" << std::endl;
  for (const PreconditionerPrecision precision : {PreconditionerPrecision::single, PreconditionerPrecision::half})
    {
      const cholesky::SparseCholesky one = factored(matrix, precision, 1), two = factored(matrix, precision, 2);
      std::vector<double>            x1(b.size()), x2(b.size());
      one.apply_preconditioner(b.data(), x1.data());
      two.apply_preconditioner(b.data(), x2.data());
      tests::check(std::string("  ") + (precision == PreconditionerPrecision::half ? "half" : "single") +
                     ": 2 threads give the bits of 1",
                   x1 == x2);
    }

  std::cout << "scaled matrices (half):" << std::endl;
  {
    std::vector<double> x(b.size());
    half.apply_preconditioner(b.data(), x.data());
    for (const double exponent : {-80., 80.})
      {
        const cholesky::SparseCholesky scaled_half = factored(scaled(matrix, std::ldexp(1., int(exponent))),
                                                              PreconditionerPrecision::half);
        std::vector<double>            y(b.size());
        scaled_half.apply_preconditioner(b.data(), y.data());
        bool same = true;
        for (std::size_t i = 0; i < b.size(); ++i)
          same = same && y[i] == std::ldexp(x[i], -int(exponent));
        tests::check("  A 2^" + format_number(exponent) + ": M^-1 b is 2^" + format_number(-exponent) +
                       " times that of A, bit for bit",
                     same);
      }
    const sparse::CSCMatrix        huge = scaled(matrix, 1e30);
    const cholesky::SparseCholesky huge_half = factored(huge, PreconditionerPrecision::half);
    tests::check_below("  A 1e30: the error over A's", preconditioner_error(huge_half, b) / half_error, 2);
  }

  std::cout << "the copy follows the factor:" << std::endl;
  {
    // A changed region (the entries coupling 3 vertices' columns), then a grasp-like update.
    const std::vector<Index> columns = sparse::local_vertex_columns(matrix, 3, 3, 3);
    sparse::CSCMatrix        changed = matrix;
    sparse::perturb_columns_spd(changed, columns, 4, 0.5);
    cholesky::SparseCholesky solver = half;
    solver.refactorize(changed, columns);
    tests::check_below("  refactorized: the error over a fresh factor's",
                       preconditioner_error(solver, b) /
                         preconditioner_error(factored(changed, PreconditionerPrecision::half), b),
                       2);
    const sparse::CSCMatrix c = sparse::penalty_columns(changed, sparse::random_columns(matrix.n_cols, 9, 4), 10.);
    // The copy is rounded when first read, or when asked beforehand: the same bits.
    cholesky::SparseCholesky rounded_first = solver;
    rounded_first.update(c);
    rounded_first.prepare_preconditioner();
    solver.update(c);
    std::vector<double> on_read(b.size()), asked(b.size());
    solver.apply_preconditioner(b.data(), on_read.data());
    rounded_first.apply_preconditioner(b.data(), asked.data());
    tests::check("  updated: rounded on first read or when asked, the same bits", on_read == asked);
    sparse::CSCMatrix updated = changed;
    sparse::add_outer_products(updated, c, 1.);
    tests::check_below("  updated: the error over a fresh factor's",
                       preconditioner_error(solver, b) /
                         preconditioner_error(factored(updated, PreconditionerPrecision::half), b),
                       2);
  }

  std::cout << "SIMD targets (half):" << std::endl;
  {
    // Each target's kernels (vectors of 4, 8 or 16 floats) against the baseline's: the
    // same blocks and rows, only the order of the sums within a vector differs.
    simd::use_target("baseline");
    std::vector<double> reference(b.size()), x(b.size());
    half.apply_preconditioner(b.data(), reference.data());
    double largest = 0;
    for (const std::string &target : simd::available_targets())
      {
        simd::use_target(target);
        half.apply_preconditioner(b.data(), x.data());
        for (std::size_t i = 0; i < b.size(); ++i)
          x[i] -= reference[i];
        largest = std::max(largest, norm(x) / norm(reference));
      }
    simd::use_target("best");
    tests::check_below("  every target against the baseline", largest, 1e-5);
  }

  std::cout << "bytes of the values:" << std::endl;
  tests::check("  half < single < full + single",
               half.numeric_bytes() < single.numeric_bytes() && single.numeric_bytes() > full.numeric_bytes());
  tests::check_below("  half / full", double(half.numeric_bytes()) / double(full.numeric_bytes()), 1.26);
}
