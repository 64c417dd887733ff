// SparseDirectCholesky::update() and downdate() with C a dealii::SparseMatrix on a
// rectangular SparsityPattern (n x 5: dense random columns on the 4 dofs of 3 cells, a
// penalty on 2 dofs): after update(C), vmult() equals a fresh initialize() of A + C C^T to
// 1e-12 and solves it, Statistics::method is update; downdate(C) then gives back A's
// solutions; a stored zero of C on a far row is left out. A downdate that would make A
// indefinite throws ExcDowndateNotPositiveDefinite and vmult() still solves A (to 1e-13
// of its solution before); C that cannot be taken (rows of two far-apart cells in one column, another
// number of rows, NaN), the left-looking method and no factorization throw the declared
// exceptions with one-line messages. refactorize() after an update takes the change back
// when given A.

#include <warpchol/lac/sparse_direct_cholesky.h>

#include "coefficient_problem.h"
#include "tests.h"

#include <limits>
#include <tuple>

using namespace dealii;
using warpchol::SparseDirectCholesky;

namespace
{
  using Entries = std::vector<std::tuple<types::global_dof_index, unsigned int, double>>;

  /** C (@p n_rows x @p n_cols) holding @p entries (row, column, value), on @p pattern. */
  SparseMatrix<double> columns_matrix(SparsityPattern &pattern, const types::global_dof_index n_rows,
                                      const unsigned int n_cols, const Entries &entries)
  {
    DynamicSparsityPattern dynamic_pattern(n_rows, n_cols);
    for (const auto &[i, t, value] : entries)
      dynamic_pattern.add(i, t);
    pattern.copy_from(dynamic_pattern);
    SparseMatrix<double> c(pattern);
    for (const auto &[i, t, value] : entries)
      c.set(i, t, value);
    return c;
  }

  /** @p matrix + @p sign C C^T (on the pattern of @p matrix). */
  void add_outer_products(SparseMatrix<double> &matrix, const Entries &entries, const double sign)
  {
    for (const auto &[i, s, a] : entries)
      for (const auto &[j, t, b] : entries)
        if (s == t && a != 0. && b != 0.)
          matrix.add(i, j, sign * a * b);
  }

  /** max |x - reference| / max |reference|. */
  double relative_difference(const Vector<double> &x, const Vector<double> &reference)
  {
    Vector<double> difference(x);
    difference -= reference;
    return difference.linfty_norm() / reference.linfty_norm();
  }

  double relative_residual(const SparseMatrix<double> &matrix, const Vector<double> &x, const Vector<double> &b)
  {
    Vector<double> residual(b.size());
    matrix.vmult(residual, x);
    residual -= b;
    return residual.l2_norm() / b.l2_norm();
  }

  /** vmult() of @p solver against a fresh initialize() of @p matrix. */
  void compare_with_fresh(const std::string &label, const SparseDirectCholesky &solver,
                          const SparseMatrix<double> &matrix, const Vector<double> &b)
  {
    SparseDirectCholesky fresh;
    fresh.initialize(matrix);
    Vector<double> x(b.size()), x_fresh(b.size());
    solver.vmult(x, b);
    fresh.vmult(x_fresh, b);
    tests::check_below(label + ": max |x - x_fresh| / max |x_fresh|", relative_difference(x, x_fresh), 1e-12);
    tests::check_below(label + ": |b - A x| / |b|", relative_residual(matrix, x, b), 1e-12);
  }
} // namespace

int main()
{
  const tests::CoefficientProblem problem(5);
  const tests::Disc               disc{Point<2>(0.5, 0.5), 0.1};
  SparseMatrix<double>            matrix;
  problem.assemble(matrix, 1., disc);
  const Vector<double>          b = problem.rhs();
  const types::global_dof_index n = matrix.m();

  // Dense random columns on the dofs of three cells (coupled in A, hence in L), a penalty
  // on two dofs, and a stored zero on the last row (left out).
  Entries                                      entries;
  tests::Random                                random(3);
  std::vector<types::global_dof_index>         dofs(problem.fe.n_dofs_per_cell());
  std::vector<std::vector<types::global_dof_index>> cell_dofs;
  for (const auto &cell : problem.dof_handler.active_cell_iterators())
    {
      cell->get_dof_indices(dofs);
      cell_dofs.push_back(dofs);
    }
  for (unsigned int t = 0; t < 3; ++t)
    for (const auto i : cell_dofs[(t + 1) * cell_dofs.size() / 4])
      entries.emplace_back(i, t, 0.5 * (2. * random.uniform() - 1.) * std::sqrt(matrix.diag_element(i)));
  entries.emplace_back(7, 3, std::sqrt(10. * matrix.diag_element(7)));
  entries.emplace_back(n / 2, 4, std::sqrt(10. * matrix.diag_element(n / 2)));
  entries.emplace_back(n - 1, 0, 0.);
  SparsityPattern            c_pattern;
  const SparseMatrix<double> c = columns_matrix(c_pattern, n, 5, entries);
  SparseMatrix<double>       updated(problem.pattern);
  updated.copy_from(matrix);
  add_outer_products(updated, entries, 1.);
  std::cout << "A: " << n << " x " << n << ", C: " << c.m() << " x " << c.n() << ", " << c.n_nonzero_elements()
            << " stored entries" << std::endl;

  SparseDirectCholesky solver;
  solver.initialize(matrix);
  solver.update(c);
  tests::check("update(): Statistics::method is update",
               solver.statistics().method == warpchol::cholesky::RefactorizationMethod::update);
  compare_with_fresh("update()", solver, updated, b);
  solver.downdate(c);
  compare_with_fresh("downdate()", solver, matrix, b);

  // refactorize() after an update, given A: the change is taken back.
  solver.update(c);
  std::vector<types::global_dof_index> rows;
  for (const auto &[i, t, value] : entries)
    rows.push_back(i);
  solver.refactorize(matrix, rows);
  compare_with_fresh("refactorize(A, rows of C) after update()", solver, matrix, b);

  // A downdate that would make A indefinite: A(7,7) becomes -A(7,7).
  Vector<double> before(n), after(n);
  solver.vmult(before, b);
  SparsityPattern indefinite_pattern;
  tests::expect_dealii_error<SparseDirectCholesky::ExcDowndateNotPositiveDefinite>("downdate() to an indefinite matrix", [&] {
    solver.downdate(columns_matrix(indefinite_pattern, n, 1, {{7, 0, std::sqrt(2. * matrix.diag_element(7))}}));
  });
  solver.vmult(after, b);
  after -= before;
  tests::check_below("  vmult() afterwards against before, relative", after.linfty_norm() / before.linfty_norm(), 1e-13);

  // C that cannot be taken (on a factorization of A made anew).
  solver.initialize(matrix);
  solver.vmult(before, b);
  SparsityPattern far_pattern, rows_pattern, nan_pattern, left_pattern;
  const auto      first = cell_dofs.front()[0], last = cell_dofs.back()[3];
  tests::expect_dealii_error<SparseDirectCholesky::ExcInvalidModification>("update(), two far-apart dofs", [&] {
    solver.update(columns_matrix(far_pattern, n, 1, {{first, 0, 1.}, {last, 0, 1.}}));
  });
  tests::expect_dealii_error<SparseDirectCholesky::ExcInvalidModification>("update(), n + 1 rows", [&] {
    solver.update(columns_matrix(rows_pattern, n + 1, 1, {{3, 0, 1.}}));
  });
  tests::expect_dealii_error<SparseDirectCholesky::ExcInvalidModification>("downdate(), NaN", [&] {
    solver.downdate(columns_matrix(nan_pattern, n, 1, {{3, 0, std::numeric_limits<double>::quiet_NaN()}}));
  });
  solver.vmult(after, b);
  after -= before;
  tests::check_below("  vmult() afterwards against before, relative", after.linfty_norm() / before.linfty_norm(), 1e-13);

  tests::expect_dealii_error<SparseDirectCholesky::ExcInvalidModification>("update(), left-looking", [&] {
    SparseDirectCholesky left;
    left.initialize(matrix, SparseDirectCholesky::AdditionalData(warpchol::cholesky::OrderingMethod::amd,
                                                                 warpchol::cholesky::FactorizationMethod::left_looking));
    left.update(c);
  });
  tests::expect_dealii_error<SparseDirectCholesky::ExcNotInitialized>("update() before initialize()", [&] {
    SparseDirectCholesky empty;
    empty.update(c);
  });
}
