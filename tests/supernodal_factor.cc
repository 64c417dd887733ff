// The supernodal factorization: its L equals the column-by-column left-looking L to 1e-12
// relative (the supernodal one stores some explicit zeros more), the solve residual is
// below 1e-12, 1 and 2 threads give the same L to rounding, the column counts of the
// skeleton-matrix algorithm equal those of the left-looking symbolic analysis, and every
// supernode's rows hold the structure of each of its columns.

#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/sparse/matrix_market.h>
#include <warpchol/sparse/residual.h>

#include "tests.h"

#include <set>

using namespace warpchol;

namespace
{
  void compare(const std::string &name, const sparse::CSCMatrix &matrix, const cholesky::OrderingMethod ordering,
               const bool relaxed)
  {
    std::cout << name << ", " << cholesky::to_string(ordering) << (relaxed ? ", relaxed" : ", fundamental")
              << ":" << std::endl;
    cholesky::SparseCholesky::Settings settings;
    settings.ordering.method = ordering;
    settings.method          = cholesky::FactorizationMethod::left_looking;
    cholesky::SparseCholesky left(settings);
    left.factorize(matrix);

    settings.method               = cholesky::FactorizationMethod::supernodal;
    settings.relaxation.enabled   = relaxed;
    cholesky::SparseCholesky supernodal(settings);
    supernodal.factorize(matrix);
    settings.n_threads = 2;
    cholesky::SparseCholesky threaded(settings);
    threaded.factorize(matrix);

    const auto &structure = supernodal.supernodal_symbolic();
    const auto &simplicial = left.symbolic();
    std::cout << "  nnz(L) = " << supernodal.statistics().nnz_l << ", supernodes: " << structure.n_supernodes()
              << ", stored values: " << structure.n_stored_values() << std::endl;
    tests::check("  same permutation as the left-looking solver", supernodal.permutation() == left.permutation());
    tests::check("  column counts (skeleton algorithm) = left-looking column counts",
                 structure.column_counts == simplicial.column_counts);
    bool rows_cover_columns = true;
    for (Index j = 0; j < structure.n; ++j)
      {
        const Index s = structure.supernode_of[j];
        const std::set<Index> rows(structure.row_index.begin() + structure.row_start[s],
                                   structure.row_index.begin() + structure.row_start[s + 1]);
        for (Index p = simplicial.column_start[j]; p < simplicial.column_start[j + 1]; ++p)
          rows_cover_columns &= rows.count(simplicial.row_index[p]) == 1;
      }
    tests::check("  every column's structure lies in its supernode's rows", rows_cover_columns);

    const sparse::CSCMatrix l_supernodal = supernodal.factor();
    tests::check_below("  |L_supernodal - L_left| / |L_left|", sparse::relative_difference(left.factor(), l_supernodal), 1e-12);
    tests::check_below("  |L_2threads - L_1thread| / |L|", sparse::relative_difference(l_supernodal, threaded.factor()), 1e-14);

    const std::vector<double> b = tests::right_hand_side_of_random_solution(matrix, 5);
    std::vector<double>       x;
    supernodal.solve(b, x);
    tests::check_below("  residual ||Ax-b||/||b||", sparse::relative_residual(matrix, x, b), 1e-12);
    const std::vector<double> x_one_thread = x;
    threaded.solve(b, x);
    tests::check_below("  residual, 2 threads (subtrees solved side by side)", sparse::relative_residual(matrix, x, b), 1e-12);
    double thread_difference = 0, size = 0;
    for (Index k = 0; k < matrix.n_cols; ++k)
      {
        thread_difference = std::max(thread_difference, std::abs(x[k] - x_one_thread[k]));
        size              = std::max(size, std::abs(x_one_thread[k]));
      }
    tests::check_below("  solution, 2 threads vs 1 (max difference / max |x|)", thread_difference / size, 1e-12);

    std::vector<double> three_b(3 * matrix.n_cols), three_x(3 * matrix.n_cols);
    for (Index k = 0; k < 3 * matrix.n_cols; ++k)
      three_b[k] = b[k % matrix.n_cols] * static_cast<double>(1 + k / matrix.n_cols);
    threaded.solve(three_b.data(), three_x.data(), 3);
    supernodal.solve(b, x);
    double largest = 0;
    for (Index k = 0; k < 3 * matrix.n_cols; ++k)
      largest = std::max(largest, std::abs(three_x[k] - x[k % matrix.n_cols] * static_cast<double>(1 + k / matrix.n_cols)));
    tests::check_below("  three right-hand sides at once (2 threads) vs one at a time (max difference)", largest, 1e-12);
  }
} // namespace

int main()
{
  for (const std::uint64_t seed : {1, 2})
    compare("random SPD n=400 seed=" + std::to_string(seed), tests::random_spd(400, 3, seed),
            cholesky::OrderingMethod::amd, true);
  compare("random SPD n=400", tests::random_spd(400, 3, 3), cholesky::OrderingMethod::natural, false);
  const sparse::CSCMatrix bcsstk16 = sparse::read_matrix_market(tests::data_file("bcsstk16.mtx"));
  for (const auto ordering : {cholesky::OrderingMethod::natural, cholesky::OrderingMethod::amd,
                              cholesky::OrderingMethod::metis})
    compare("bcsstk16", bcsstk16, ordering, true);
  compare("bcsstk16", bcsstk16, cholesky::OrderingMethod::metis, false);

  std::cout << "bad input:" << std::endl;
  tests::expect_error("not positive definite, supernodal", [] {
    sparse::CSCMatrix matrix = tests::random_spd(300, 3, 4);
    matrix.values[matrix.column_start[150]] = -1.; // the diagonal of column 150
    cholesky::SparseCholesky::Settings settings;
    settings.method = cholesky::FactorizationMethod::supernodal;
    cholesky::SparseCholesky solver(settings);
    solver.factorize(matrix);
  });
}
