// update(), downdate() and modify() refuse what they cannot do, with a one-line message
// (printed): before analyze() or a factorization, the left-looking method, changes
// pending (refactorize(..., Refresh::none)), C with another number of rows, a row out of
// range, rows not sorted, a value that is not finite, a column whose rows the factor does
// not couple (two far-apart dofs: C C^T would fill L outside its pattern; the message
// names both in the user's numbering), signs of another count or other than +1 and -1.
// None of them changes the factor.

#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/sparse/matrix_market.h>
#include <warpchol/sparse/spd_perturbation.h>

#include "modification_tests.h"
#include "tests.h"

#include <limits>

using namespace warpchol;

namespace
{
  /** C (n x 1) with @p values on @p rows (user numbering, in the order given). */
  sparse::CSCMatrix one_column(const Index n, const std::vector<Index> &rows, const std::vector<double> &values)
  {
    sparse::CSCMatrix c = sparse::CSCMatrix::zero(n, 1);
    c.row_index         = rows;
    c.values            = values;
    c.column_start      = {0, static_cast<Index>(rows.size())};
    return c;
  }
} // namespace

int main()
{
  const sparse::CSCMatrix matrix = sparse::read_matrix_market(tests::data_file("bcsstk16.mtx"));
  const Index             n      = matrix.n_cols;
  const cholesky::SparseCholesky::Settings settings = tests::supernodal_metis();
  const sparse::CSCMatrix penalty = sparse::penalty_columns(matrix, {0, 1}, 1.);

  tests::expect_error("update() before analyze()", [&] { cholesky::SparseCholesky(settings).update(penalty); });
  tests::expect_error("update() before factorize()", [&] {
    cholesky::SparseCholesky solver(settings);
    solver.analyze(matrix);
    solver.update(penalty);
  });
  tests::expect_error("downdate(), left-looking method", [&] {
    cholesky::SparseCholesky::Settings left = settings;
    left.method                             = cholesky::FactorizationMethod::left_looking;
    cholesky::SparseCholesky solver(left);
    solver.factorize(matrix);
    solver.downdate(penalty);
  });

  cholesky::SparseCholesky solver(settings);
  solver.analyze(matrix);
  solver.factorize(matrix);
  const sparse::CSCMatrix factor = solver.factor();

  tests::expect_error("C with n + 1 rows", [&] {
    sparse::CSCMatrix c = penalty;
    c.n_rows            = n + 1;
    solver.update(c);
  });
  tests::expect_error("a row out of range", [&] { solver.update(one_column(n, {n}, {1.})); });
  tests::expect_error("rows not sorted", [&] { solver.update(one_column(n, {5, 4}, {1., 1.})); });
  tests::expect_error("NaN in C", [&] { solver.update(one_column(n, {4, 5}, {1., std::nan("")})); });
  tests::expect_error("infinity in C",
                      [&] { solver.downdate(one_column(n, {7}, {-std::numeric_limits<double>::infinity()})); });

  // Two dofs far apart: the first column of P^T A P (a leaf) and one not on its path.
  const std::vector<Index> &perm   = solver.permutation();
  const std::vector<Index> &parent = solver.elimination_tree();
  std::vector<bool>         on_path(n, false);
  for (Index j = 0; j != -1; j = parent[j])
    on_path[j] = true;
  Index far = n / 2;
  while (on_path[far])
    ++far;
  std::cout << "far apart: columns " << perm[0] << " and " << perm[far] << " (permuted 0 and " << far << ")" << std::endl;
  tests::expect_error("a column coupling two far-apart dofs", [&] {
    solver.update(one_column(n, std::vector<Index>{std::min(perm[0], perm[far]), std::max(perm[0], perm[far])},
                             {1., 1.}));
  });
  tests::expect_error("the same among valid columns, in a downdate", [&] {
    sparse::CSCMatrix far_apart = one_column(
      n, std::vector<Index>{std::min(perm[0], perm[far]), std::max(perm[0], perm[far])}, {1., 1.});
    solver.downdate(tests::side_by_side(penalty, far_apart, false));
  });

  tests::expect_error("modify(), 2 columns and 1 sign", [&] { solver.modify(penalty, {1.}); });
  tests::expect_error("modify(), a sign 0.5", [&] { solver.modify(penalty, {1., 0.5}); });

  // Changes loaded but pending: the factor is not that of the loaded matrix.
  sparse::CSCMatrix changed = matrix;
  sparse::perturb_columns_spd(changed, {10, 11, 12}, 1);
  solver.refactorize(changed, {10, 11, 12}, cholesky::Refresh::none);
  tests::expect_error("update() with changes pending", [&] { solver.update(penalty); });
  tests::check("the factor is bit for bit as it was", tests::same_bits(factor, solver.factor()));
  solver.refactorize(changed, {});
  solver.update(penalty);
  tests::check("after refactorize(), update() runs", solver.statistics().method == cholesky::RefactorizationMethod::update);
}
