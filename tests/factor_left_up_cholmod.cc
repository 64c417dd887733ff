// Left-looking L equals up-looking L and CHOLMOD's simplicial L (same permutation) to
// 1e-12 relative, and the solve residual ||Ax-b||/||b|| is below 1e-12, on random SPD
// matrices and on bcsstk16, with the natural, AMD and METIS orderings.

#include <warpchol/backends/cholmod_reference.h>
#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/sparse/conversions.h>
#include <warpchol/sparse/matrix_market.h>
#include <warpchol/sparse/residual.h>

#include "tests.h"

using namespace warpchol;

namespace
{
  void compare(const std::string &name, const sparse::CSCMatrix &matrix,
               const cholesky::OrderingMethod ordering)
  {
    std::cout << name << ", " << cholesky::to_string(ordering) << ":" << std::endl;
    cholesky::SparseCholesky::Settings settings;
    settings.ordering.method = ordering;
    settings.method          = cholesky::FactorizationMethod::left_looking;
    cholesky::SparseCholesky left(settings);
    left.factorize(matrix); // analyzes on first use
    settings.method = cholesky::FactorizationMethod::up_looking;
    cholesky::SparseCholesky up(settings);
    up.factorize(matrix);
    std::cout << "  n = " << left.statistics().n << ", nnz(tril A) = " << left.statistics().nnz_a
              << ", nnz(L) = " << left.statistics().nnz_l << std::endl;

    const sparse::CSCMatrix l_left = left.factor();
    tests::check("  same permutation for both methods", left.permutation() == up.permutation());
    tests::check_below("  |L_left - L_up| / |L_left|", sparse::relative_difference(l_left, up.factor()), 1e-12);

    cholesky::CholmodReference cholmod(false);
    cholmod.analyze(matrix, left.permutation());
    cholmod.factorize(matrix);
    tests::check_below("  |L_left - L_cholmod| / |L_left|", sparse::relative_difference(l_left, cholmod.factor()), 1e-12);

    const std::vector<double> b = tests::right_hand_side_of_random_solution(matrix, 7);
    std::vector<double>       x;
    left.solve(b, x);
    tests::check_below("  left-looking residual ||Ax-b||/||b||", sparse::relative_residual(matrix, x, b), 1e-12);
    up.solve(b, x);
    tests::check_below("  up-looking residual ||Ax-b||/||b||", sparse::relative_residual(matrix, x, b), 1e-12);

    // Several right-hand sides at once give the same solutions as one at a time.
    std::vector<double> two_b(2 * matrix.n_cols), two_x(2 * matrix.n_cols);
    std::copy(b.begin(), b.end(), two_b.begin());
    const std::vector<double> other_b = tests::right_hand_side_of_random_solution(matrix, 8);
    std::copy(other_b.begin(), other_b.end(), two_b.begin() + matrix.n_cols);
    left.solve(two_b.data(), two_x.data(), 2);
    left.solve(b, x);
    tests::check("  two right-hand sides: first solution as alone",
                 std::equal(x.begin(), x.end(), two_x.begin()));
  }
} // namespace

int main()
{
  const std::vector<cholesky::OrderingMethod> orderings = {cholesky::OrderingMethod::natural,
                                                           cholesky::OrderingMethod::amd,
                                                           cholesky::OrderingMethod::metis};
  for (const std::uint64_t seed : {1, 2, 3})
    for (const auto ordering : orderings)
      compare("random SPD n=300 seed=" + std::to_string(seed), tests::random_spd(300, 3, seed), ordering);
  for (const auto ordering : orderings)
    compare("random SPD n=1500", tests::random_spd(1500, 4, 11), ordering);

  const sparse::CSCMatrix bcsstk16 = sparse::read_matrix_market(tests::data_file("bcsstk16.mtx"));
  for (const auto ordering : orderings)
    compare("bcsstk16", bcsstk16, ordering);
  // The same matrix with both triangles stored gives the same factor.
  compare("bcsstk16 (full storage)", sparse::to_full_storage(bcsstk16), cholesky::OrderingMethod::amd);
}
