// Partial refactorization, column by column and supernodal (1 and 2 threads), after
// changing column sets (one column, a leaf of the elimination tree, the root, a
// vertex-like neighbourhood, 10 %, all, none): the updated L equals a full factorization
// of the new matrix to 1e-13 relative, the dirty columns are exactly the elimination-tree
// closure of the changed ones (found here independently, by reachability in the graph of
// L), and the columns outside it (outside its supernodes, for the supernodal method) are
// reused bit for bit. Column by column, they also equal those of a full factorization bit
// for bit: a column depends on nothing outside its subtree.

#include <warpchol/cholesky/ordering.h>
#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/sparse/conversions.h>
#include <warpchol/sparse/matrix_market.h>
#include <warpchol/sparse/residual.h>
#include <warpchol/sparse/spd_perturbation.h>

#include "tests.h"

#include <set>

using namespace warpchol;

namespace
{
  /** Columns reachable from @p seeds through the structure of L (j -> rows of L(:,j)). */
  std::vector<Index> reachable_in_l(const sparse::CSCMatrix &l, const std::vector<Index> &seeds)
  {
    std::set<Index>    reached(seeds.begin(), seeds.end());
    std::vector<Index> stack(seeds.begin(), seeds.end());
    while (!stack.empty())
      {
        const Index j = stack.back();
        stack.pop_back();
        for (Index p = l.column_start[j] + 1; p < l.column_start[j + 1]; ++p)
          if (l.values[p] != 0. && reached.insert(l.row_index[p]).second)
            stack.push_back(l.row_index[p]);
      }
    return {reached.begin(), reached.end()};
  }

  bool column_bitwise_equal(const sparse::CSCMatrix &a, const sparse::CSCMatrix &b, const Index j)
  {
    return std::equal(a.values.begin() + a.column_start[j], a.values.begin() + a.column_start[j + 1],
                      b.values.begin() + b.column_start[j]);
  }

  void run_case(const std::string &label, cholesky::SparseCholesky &solver, sparse::CSCMatrix &matrix,
                const std::vector<Index> &changed, const std::uint64_t seed)
  {
    const sparse::CSCMatrix old_factor = solver.factor();
    sparse::perturb_columns_spd(matrix, changed, seed);
    solver.refactorize(matrix, changed);

    cholesky::SparseCholesky full = solver; // same analysis, same permutation
    full.factorize(matrix);
    const sparse::CSCMatrix updated = solver.factor(), refactored = full.factor();

    const auto        &stats   = solver.statistics();
    std::vector<Index> permuted_changed;
    const std::vector<Index> inverse = cholesky::invert_permutation(solver.permutation());
    for (const Index j : changed)
      permuted_changed.push_back(inverse[j]);
    // Reachability through the nonzeros of L (the explicit zeros of supernodal padding
    // carry no dependency).
    const std::vector<Index> expected = reachable_in_l(old_factor, permuted_changed);

    // Columns that may have been recomputed: the closure, widened to whole supernodes.
    std::set<Index> recomputed(solver.recomputed_columns().begin(), solver.recomputed_columns().end());
    const auto &structure = solver.supernodal_symbolic();
    if (structure.n_supernodes() > 0)
      for (const Index j : solver.recomputed_columns())
        {
          const Index s = structure.supernode_of[j];
          for (Index c = structure.first_column[s]; c < structure.first_column[s + 1]; ++c)
            recomputed.insert(c);
        }
    bool clean_columns_unchanged = true;
    for (Index j = 0; j < stats.n; ++j)
      if (recomputed.count(j) == 0)
        clean_columns_unchanged &= column_bitwise_equal(old_factor, updated, j);

    std::cout << "  " << label << ": " << changed.size() << " changed, " << solver.recomputed_columns().size()
              << " dirty columns, " << stats.columns_recomputed << " recomputed";
    if (structure.n_supernodes() > 0)
      std::cout << " in " << stats.supernodes_recomputed << " supernodes";
    std::cout << ", flop fraction " << format_number(stats.flops_recomputed / stats.flops, 3) << std::endl;
    tests::check_below("    |L_partial - L_full| / |L_full|", sparse::relative_difference(refactored, updated), 1e-13);
    if (structure.n_supernodes() == 0)
      {
        bool same_as_full = true;
        for (Index j = 0; j < stats.n; ++j)
          if (recomputed.count(j) == 0)
            same_as_full &= column_bitwise_equal(refactored, updated, j);
        tests::check("    they equal those of a full factorization bit for bit", same_as_full);
      }
    tests::check("    dirty columns = etree closure of the changed columns", solver.recomputed_columns() == expected);
    tests::check("    columns outside the dirty ones are reused bit for bit", clean_columns_unchanged);

    std::vector<double> ones(stats.n, 1.), b(stats.n), x;
    matrix.vmult(ones.data(), b.data());
    solver.solve(b, x);
    tests::check_below("    residual ||Ax-b||/||b||", sparse::relative_residual(matrix, x, b), 1e-12);
  }

  void run_all_cases(const std::string &name, sparse::CSCMatrix matrix, const cholesky::OrderingMethod ordering,
                     const cholesky::FactorizationMethod method = cholesky::FactorizationMethod::left_looking,
                     const unsigned int                  n_threads = 1)
  {
    std::cout << name << ", " << cholesky::to_string(ordering) << ", " << cholesky::to_string(method)
              << ", " << n_threads << " thread(s):" << std::endl;
    cholesky::SparseCholesky::Settings settings;
    settings.ordering.method = ordering;
    settings.method          = method;
    settings.n_threads       = n_threads;
    // Partial refactorization itself, not the update refactorize() may choose instead.
    settings.change_method = cholesky::ChangeMethod::recompute;
    cholesky::SparseCholesky solver(settings);
    solver.analyze(matrix);
    solver.factorize(matrix);
    const Index               n      = matrix.n_cols;
    const std::vector<Index> &perm   = solver.permutation();
    const auto               &parent = solver.elimination_tree();

    // A leaf of the elimination tree (no child), taken in the middle of the ordering.
    std::vector<bool> has_child(n, false);
    for (Index j = 0; j < n; ++j)
      if (parent[j] != -1)
        has_child[parent[j]] = true;
    Index leaf = n / 2;
    while (has_child[leaf])
      ++leaf;
    // A vertex-like neighbourhood: a column and the columns it couples to.
    const sparse::CSCMatrix full  = sparse::to_full_storage(matrix);
    const Index             centre = n / 3;
    std::vector<Index>      neighbourhood(full.row_index.begin() + full.column_start[centre],
                                          full.row_index.begin() + full.column_start[centre + 1]);
    std::vector<Index> everything(n);
    for (Index j = 0; j < n; ++j)
      everything[j] = j;

    run_case("one column", solver, matrix, {n / 5}, 1);
    run_case("a leaf", solver, matrix, {perm[leaf]}, 2);
    run_case("the root", solver, matrix, {perm[n - 1]}, 3);
    run_case("a neighbourhood", solver, matrix, neighbourhood, 4);
    run_case("10 %", solver, matrix, sparse::random_columns(n, n / 10, 5), 5);
    run_case("all", solver, matrix, everything, 6);
    run_case("none", solver, matrix, {}, 7);
  }
} // namespace

int main()
{
  const sparse::CSCMatrix bcsstk16 = sparse::read_matrix_market(tests::data_file("bcsstk16.mtx"));
  run_all_cases("bcsstk16", bcsstk16, cholesky::OrderingMethod::metis);
  run_all_cases("bcsstk16", bcsstk16, cholesky::OrderingMethod::amd);
  run_all_cases("bcsstk16 (full storage)", sparse::to_full_storage(bcsstk16), cholesky::OrderingMethod::metis);
  run_all_cases("random SPD n=1000", tests::random_spd(1000, 3, 5), cholesky::OrderingMethod::amd);
  const auto supernodal = cholesky::FactorizationMethod::supernodal;
  run_all_cases("bcsstk16", bcsstk16, cholesky::OrderingMethod::metis, supernodal, 1);
  run_all_cases("bcsstk16", bcsstk16, cholesky::OrderingMethod::metis, supernodal, 2);
  run_all_cases("bcsstk16", bcsstk16, cholesky::OrderingMethod::amd, supernodal, 2);
  run_all_cases("random SPD n=1000", tests::random_spd(1000, 3, 5), cholesky::OrderingMethod::amd, supernodal, 1);

  // A change the caller does not list is found while loading the values and recomputed.
  std::cout << "unlisted change:" << std::endl;
  sparse::CSCMatrix        matrix = tests::random_spd(500, 3, 9);
  cholesky::SparseCholesky solver;
  solver.factorize(matrix);
  sparse::perturb_columns_spd(matrix, {10, 20}, 1);
  solver.refactorize(matrix, {10});
  cholesky::SparseCholesky full = solver;
  full.factorize(matrix);
  tests::check_below("  |L_partial - L_full| / |L_full|", sparse::relative_difference(full.factor(), solver.factor()), 1e-13);

  // A complete listing: only the listed columns are read. Listed right, the factor is that
  // of the new matrix; a change left out is not seen until a search finds it.
  std::cout << "complete listing:" << std::endl;
  const sparse::CSCMatrix before = matrix;
  sparse::perturb_columns_spd(matrix, {30, 40}, 2);
  const std::vector<Index> listed = sparse::changed_columns(before, matrix);
  solver.refactorize(matrix, listed, cholesky::Refresh::all, cholesky::ChangeListing::complete);
  full.factorize(matrix);
  tests::check_below("  listed: |L_partial - L_full| / |L_full|", sparse::relative_difference(full.factor(), solver.factor()),
                     1e-13);
  const sparse::CSCMatrix listed_factor = solver.factor();
  sparse::perturb_columns_spd(matrix, {50}, 3);
  solver.refactorize(matrix, {}, cholesky::Refresh::all, cholesky::ChangeListing::complete);
  tests::check("  a change left out is not read", solver.factor().values == listed_factor.values);
  solver.refactorize(matrix, {});
  full.factorize(matrix);
  tests::check_below("  then searched: |L_partial - L_full| / |L_full|",
                     sparse::relative_difference(full.factor(), solver.factor()), 1e-13);
}
