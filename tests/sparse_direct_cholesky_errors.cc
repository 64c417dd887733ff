// SparseDirectCholesky's errors are deal.II exceptions of the types it declares, thrown in
// Release builds too, each with a one-line message that says what and where: no
// factorization (before initialize(), after a failed one), a matrix that is not positive
// definite (column and pivot), not symmetric (both entries), not square, with a value
// that is not finite, or of another pattern than the analyzed one; a changed row out of
// range; a vector of the wrong size. A failed refactorization leaves no factorization,
// and the next one factors in full.

#include <warpchol/lac/sparse_direct_cholesky.h>

#include "coefficient_problem.h"
#include "tests.h"

#include <limits>
#include <tuple>

using namespace dealii;
using warpchol::SparseDirectCholesky;

namespace
{
  /** An @p n_rows x @p n_cols matrix of the given entries (row, column, value), on @p pattern. */
  SparseMatrix<double> small_matrix(SparsityPattern &pattern, const unsigned int n_rows, const unsigned int n_cols,
                                    const std::vector<std::tuple<unsigned int, unsigned int, double>> &entries)
  {
    DynamicSparsityPattern dynamic_pattern(n_rows, n_cols);
    for (const auto &[i, j, value] : entries)
      dynamic_pattern.add(i, j);
    pattern.copy_from(dynamic_pattern);
    SparseMatrix<double> matrix(pattern);
    for (const auto &[i, j, value] : entries)
      matrix.set(i, j, value);
    return matrix;
  }
} // namespace

int main()
{
  const tests::CoefficientProblem problem(3);
  const tests::Disc               disc{Point<2>(0.5, 0.5), 0.2};
  SparseMatrix<double>            matrix;
  problem.assemble(matrix, 1., disc);
  const Vector<double> b = problem.rhs();
  const auto           n = matrix.m();

  using Solver = SparseDirectCholesky;
  tests::expect_dealii_error<Solver::ExcNotInitialized>("vmult before initialize()", [&] {
    const Solver   solver;
    Vector<double> x(b.size());
    solver.vmult(x, b);
  });
  tests::expect_dealii_error<Solver::ExcNotInitialized>("refactorize() before initialize()", [&] {
    Solver solver;
    solver.refactorize(matrix, {0});
  });

  SparsityPattern pattern;
  tests::expect_dealii_error<Solver::ExcInvalidMatrix>("not square", [&] {
    Solver solver;
    solver.initialize(small_matrix(pattern, 2, 3, {{0, 0, 1.}, {1, 1, 1.}, {1, 2, 1.}}));
  });
  tests::expect_dealii_error<Solver::ExcInvalidMatrix>("not symmetric", [&] {
    Solver solver;
    solver.initialize(small_matrix(pattern, 2, 2, {{0, 0, 4.}, {0, 1, 1.}, {1, 0, 2.}, {1, 1, 4.}}));
  });
  tests::expect_dealii_error<Solver::ExcNotPositiveDefinite>("not positive definite", [&] {
    Solver solver;
    solver.initialize(small_matrix(pattern, 2, 2, {{0, 0, 1.}, {0, 1, 2.}, {1, 0, 2.}, {1, 1, 1.}}));
  });

  Solver solver;
  solver.initialize(matrix);
  tests::expect_dealii_error<Solver::ExcRowOutOfRange>("changed row out of range", [&] { solver.refactorize(matrix, {3, n}); });
  tests::expect_dealii_error<ExcDimensionMismatch>("vector of the wrong size", [&] {
    Vector<double> x(n + 1);
    solver.vmult(x, b);
  });
  tests::expect_dealii_error<Solver::ExcInvalidMatrix>("another sparsity pattern", [&] {
    const tests::CoefficientProblem finer(4);
    SparseMatrix<double>            other;
    finer.assemble(other, 1., disc);
    solver.refactorize(other, {0});
  });

  SparseMatrix<double> broken;
  problem.assemble(broken, 1., disc);
  broken.set(5, 5, std::numeric_limits<double>::quiet_NaN());
  tests::expect_dealii_error<Solver::ExcInvalidMatrix>("a value that is not finite", [&] { solver.refactorize(broken, {5}); });
  tests::expect_dealii_error<Solver::ExcNotInitialized>("vmult after the failed refactorization", [&] {
    Vector<double> x(n);
    solver.vmult(x, b);
  });
  broken.set(5, 5, -1e6);
  tests::expect_dealii_error<Solver::ExcNotPositiveDefinite>("a negative diagonal", [&] { solver.refactorize(broken, {5}); });

  // The next refactorization factors everything again.
  solver.refactorize(matrix, {5});
  Vector<double> x(n), residual(n);
  solver.vmult(x, b);
  matrix.vmult(residual, x);
  residual -= b;
  tests::check("after the failures, refactorize() factors in full",
               solver.statistics().columns_recomputed == static_cast<warpchol::Index>(n));
  tests::check_below("  |b - A x| / |b|", residual.l2_norm() / b.l2_norm(), 1e-12);
}
