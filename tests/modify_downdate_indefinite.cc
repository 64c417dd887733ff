// A downdate that would make A indefinite (bcsstk16, supernodal, METIS): C =
// sqrt(2 A(j,j)) e_j turns A(j,j) into -A(j,j). downdate() throws NotPositiveDefinite
// naming the column (the message is printed), and the factor is left that of the matrix
// as it was (its paths' columns recomputed from the copy of A: within 1e-14 of the factor
// before), whether the pivot fails at once (a leaf: its ancestors untouched), after other
// columns of C changed the supernodes below (the root, last), or in the second group of
// 64 columns (rank 65), on 1 thread and on 2 (a leaf's pivot among 16 columns on other
// paths, which run beside it); solve() still solves A to 1e-12. After an update whose
// product falls outside A's pattern (the copy of A then no longer holds the factored
// matrix), the failed downdate puts back the copy it kept, bit for bit. A downdate that keeps A
// positive definite (c^T A^-1 c = 1/2) then equals a fresh factorization of A - c c^T.
//
// Through refactorize(A', changed) with ChangeMethod::update: a penalty on the 9 dofs of
// 3 vertices is taken as an update (Statistics::method), of rank 9, with the chooser's
// flops and predictions positive, and equals a fresh factorization; its removal (a
// downdate through refactorize) too. An indefinite A' is tried as a downdate, falls back
// (update_fell_back) and the recomputation throws NotPositiveDefinite in the user's
// numbering; factorize() then starts again.

#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/sparse/matrix_market.h>
#include <warpchol/sparse/residual.h>
#include <warpchol/sparse/spd_perturbation.h>

#include "modification_tests.h"
#include "tests.h"

using namespace warpchol;

namespace
{
  /** downdate() by @p c of a copy of @p base must fail and leave the factor that of @p matrix. */
  void check_failed_downdate(const std::string &label, const cholesky::SparseCholesky &base,
                             const sparse::CSCMatrix &matrix, const sparse::CSCMatrix &c)
  {
    std::cout << label << ":" << std::endl;
    cholesky::SparseCholesky solver = base;
    const sparse::CSCMatrix  before = solver.factor();
    const Index             n_updates = solver.statistics().n_updates;
    tests::expect_error("  downdate()", [&] { solver.downdate(c); });
    tests::check_below("  the factor against the one before, relative",
                       sparse::relative_difference(solver.factor(), before), 1e-14);
    tests::check("  the factor is still exact", solver.factor_is_exact());
    tests::check("  no update counted", solver.statistics().n_updates == n_updates);
    tests::check_below("  solve(): ||A x - b|| / ||b||", tests::solve_residual(solver, matrix), 1e-12);
  }
} // namespace

// The cases in the order of the .output file, each a few checks: a list, kept in one place.
int main()
{
  const sparse::CSCMatrix matrix = sparse::read_matrix_market(tests::data_file("bcsstk16.mtx"));
  const Index             n      = matrix.n_cols;
  cholesky::SparseCholesky::Settings settings = tests::supernodal_metis();
  cholesky::SparseCholesky solver(settings);
  solver.analyze(matrix);
  solver.factorize(matrix);
  const std::vector<Index> &perm   = solver.permutation();
  const std::vector<Index> &parent = solver.elimination_tree();
  // A leaf of the elimination tree whose path to the root is long (bcsstk16 has columns
  // coupled to none: those are roots of their own), in the first supernode that has one.
  std::vector<bool> has_child(n, false);
  for (Index j = 0; j < n; ++j)
    if (parent[j] != -1)
      has_child[parent[j]] = true;
  const auto path_length = [&](Index j) {
    Index length = 0;
    for (; j != -1; j = parent[j])
      ++length;
    return length;
  };
  Index permuted_leaf = 0;
  while (has_child[permuted_leaf] || path_length(permuted_leaf) < 100)
    ++permuted_leaf;
  const Index leaf = perm[permuted_leaf], root = perm[n - 1];
  std::cout << "bcsstk16: n = " << n << ", leaf column " << leaf << " (path of " << path_length(permuted_leaf)
            << " columns), root column " << root << std::endl;

  // sqrt(2 A(j,j)) e_j: A(j,j) becomes -A(j,j).
  const auto indefinite = [&](const Index j) { return sparse::penalty_columns(matrix, {j}, 2.); };
  check_failed_downdate("a leaf's pivot", solver, matrix, indefinite(leaf));
  cholesky::SparseCholesky two_threads = solver;
  two_threads.set_thread_count(2);
  check_failed_downdate("a leaf's pivot, 2 threads", two_threads, matrix,
                        tests::side_by_side(sparse::penalty_columns(matrix, sparse::random_columns(n, 16, 2), 1e-3),
                                            indefinite(leaf), false));

  // Small downdates on leaves of other paths, then the root's pivot fails: the supernodes
  // on their paths were changed before it.
  std::vector<Index> small;
  for (const Index column : sparse::random_columns(n, 8, 3))
    small.push_back(column);
  sparse::CSCMatrix late = tests::side_by_side(sparse::penalty_columns(matrix, small, 1e-3), indefinite(root), false);
  check_failed_downdate("the root's pivot, after 8 columns on other paths", solver, matrix, late);

  // The same in the second group of 64 columns of C.
  sparse::CSCMatrix second_group =
    tests::side_by_side(sparse::penalty_columns(matrix, sparse::random_columns(n, 64, 4), 1e-3), indefinite(root), false);
  check_failed_downdate("the root's pivot, column 65 (second group)", solver, matrix, second_group);

  // An update on two dofs that only L couples (a fill entry): its product falls outside
  // A's pattern, so the copy of A no longer holds the factored matrix, and a failed
  // downdate puts back the copy it kept as it went.
  {
    std::cout << "after an update outside A's pattern:" << std::endl;
    const sparse::CSCMatrix l       = solver.factor();
    const auto              coupled = [&](const Index r, const Index c) {
      for (const auto [row, column] : {std::pair(r, c), std::pair(c, r)})
        for (Index k = matrix.column_start[column]; k < matrix.column_start[column + 1]; ++k)
          if (matrix.row_index[k] == row)
            return true;
      return false;
    };
    Index fill_row = -1, fill_column = -1;
    for (Index j = 0; j < n && fill_row < 0; ++j)
      for (Index k = l.column_start[j]; k < l.column_start[j + 1] && fill_row < 0; ++k)
        if (l.row_index[k] != j && !coupled(perm[l.row_index[k]], perm[j]))
          {
            fill_row    = l.row_index[k];
            fill_column = j;
          }
    sparse::CSCMatrix fill = sparse::CSCMatrix::zero(n, 1);
    fill.row_index         = {std::min(perm[fill_row], perm[fill_column]), std::max(perm[fill_row], perm[fill_column])};
    fill.values            = {1e-3, 1e-3};
    fill.column_start      = {0, 2};
    cholesky::SparseCholesky outside = solver;
    outside.update(fill);
    const sparse::CSCMatrix before = outside.factor();
    tests::expect_error("  downdate()", [&] { outside.downdate(indefinite(leaf)); });
    tests::check("  the factor is bit for bit as it was", tests::same_bits(before, outside.factor()));
    tests::check("  the factor is still exact", outside.factor_is_exact());
  }

  // c^T A^-1 c = 1/2: A - c c^T is positive definite.
  std::cout << "a downdate that keeps A positive definite:" << std::endl;
  std::vector<double> unit(n, 0.), inverse_column;
  unit[leaf] = 1.;
  solver.solve(unit, inverse_column);
  sparse::CSCMatrix c = sparse::CSCMatrix::zero(n, 1);
  c.row_index         = {leaf};
  c.values            = {std::sqrt(0.5 / inverse_column[leaf])};
  c.column_start      = {0, 1};
  sparse::CSCMatrix downdated = matrix;
  sparse::add_outer_products(downdated, c, -1.);
  solver.downdate(c);
  tests::check_below("  |L_downdate - L_fresh| / |L_fresh|",
                     sparse::relative_difference(tests::fresh_factorization(solver, downdated).factor(), solver.factor()),
                     1e-12);
  tests::check_below("  ||(A - c c^T) x - b|| / ||b||", tests::solve_residual(solver, downdated), 1e-12);
  tests::check("  Statistics::method is update", solver.statistics().method == cholesky::RefactorizationMethod::update);

  // Through refactorize() with ChangeMethod::update.
  std::cout << "refactorize(), ChangeMethod::update:" << std::endl;
  settings.change_method = cholesky::ChangeMethod::update;
  cholesky::SparseCholesky chooser(settings);
  chooser.analyze(matrix);
  chooser.factorize(matrix);
  const std::vector<Index> dofs = sparse::local_vertex_columns(matrix, 3, 3, 5);
  sparse::CSCMatrix        penalized = matrix;
  sparse::add_outer_products(penalized, sparse::penalty_columns(matrix, dofs, 1.), 1.);
  chooser.refactorize(penalized, dofs);
  const auto &stats = chooser.statistics();
  std::cout << "  a penalty on " << dofs.size() << " dofs: " << cholesky::to_string(stats.method) << ", rank "
            << stats.update_rank << std::endl;
  tests::check("  taken as an update", stats.method == cholesky::RefactorizationMethod::update);
  tests::check("  of rank 9", stats.update_rank == 9);
  tests::check("  update and partial flops positive", stats.update_flops > 0 && stats.partial_flops > 0);
  tests::check("  predicted seconds of update, partial and full positive",
               stats.predicted_update_seconds > 0 && stats.predicted_partial_seconds > 0 &&
                 stats.predicted_full_seconds > 0);
  tests::check("  no fallback", !stats.update_fell_back);
  tests::check_below("  |L_update - L_fresh| / |L_fresh|",
                     sparse::relative_difference(tests::fresh_factorization(chooser, penalized).factor(), chooser.factor()),
                     1e-12);
  chooser.refactorize(matrix, dofs);
  std::cout << "  the penalty removed: " << cholesky::to_string(stats.method) << ", rank " << stats.update_rank
            << std::endl;
  tests::check("  taken as an update (a downdate)", stats.method == cholesky::RefactorizationMethod::update);
  tests::check_below("  |L_downdate - L_fresh| / |L_fresh|",
                     sparse::relative_difference(tests::fresh_factorization(chooser, matrix).factor(), chooser.factor()),
                     1e-12);
  tests::check("  two updates counted", stats.n_updates == 2);

  sparse::CSCMatrix indefinite_matrix = matrix;
  sparse::add_outer_products(indefinite_matrix, indefinite(leaf), -1.);
  tests::expect_error("  refactorize() of an indefinite A'", [&] { chooser.refactorize(indefinite_matrix, {leaf}); });
  tests::check("  the downdate was tried and fell back to recomputing", stats.update_fell_back);
  tests::check("  no valid factor is left", !chooser.factor_is_exact());
  chooser.factorize(matrix);
  tests::check_below("  factorize() of A again: ||A x - b|| / ||b||", tests::solve_residual(chooser, matrix), 1e-12);

  // A downdate stopped by the pivot tolerance although A' is positive definite: the
  // recomputation that follows gives the factor of A'.
  std::cout << "refactorize(), a downdate stopped by Settings::downdate_pivot_tolerance = 0.9:" << std::endl;
  settings.downdate_pivot_tolerance = 0.9;
  cholesky::SparseCholesky strict(settings);
  strict.analyze(matrix);
  strict.factorize(penalized);
  strict.refactorize(matrix, dofs);
  tests::check("  the downdate was tried and fell back to recomputing", strict.statistics().update_fell_back &&
                                                                         strict.statistics().method ==
                                                                           cholesky::RefactorizationMethod::partial);
  tests::check_below("  |L - L_fresh| / |L_fresh|",
                     sparse::relative_difference(tests::fresh_factorization(strict, matrix).factor(), strict.factor()),
                     1e-12);
  tests::check_below("  ||A x - b|| / ||b||", tests::solve_residual(strict, matrix), 1e-12);
}
