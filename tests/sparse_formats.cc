// The sparse formats represent the same matrix after every conversion: CSC <-> CSR,
// CSC <-> BSC (3x3 blocks), lower <-> full storage, a deal.II SparseMatrix -> CSC (and
// copy_values for new values), and a Matrix Market write/read round trip (bit exact).

#include <warpchol/sparse/conversions.h>
#include <warpchol/sparse/dealii_conversion.h>
#include <warpchol/sparse/matrix_market.h>
#include <warpchol/sparse/residual.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

#include "tests.h"

#include <cstdio>

using namespace warpchol;

namespace
{
  std::vector<double> product(const sparse::CSCMatrix &a, const std::vector<double> &x)
  {
    std::vector<double> y(a.n_rows);
    a.vmult(x.data(), y.data());
    return y;
  }

  double max_difference(const std::vector<double> &a, const std::vector<double> &b)
  {
    double largest = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
      largest = std::max(largest, std::abs(a[i] - b[i]));
    return largest;
  }
} // namespace

int main()
{
  const sparse::CSCMatrix lower = tests::random_spd(30, 3, 4);
  const sparse::CSCMatrix full  = sparse::to_full_storage(lower);
  std::vector<double>     x(30);
  tests::Random           random(3);
  for (double &v : x)
    v = random.uniform();
  const std::vector<double> y = product(lower, x);

  std::cout << "lower storage: " << lower.n_nonzeros() << " entries, full: " << full.n_nonzeros() << std::endl;
  full.check_consistency();
  tests::check("full storage is consistent and symmetric",
               sparse::relative_difference(full, sparse::transpose(full)) == 0.);
  tests::check_below("lower vs full product", max_difference(y, product(full, x)), 1e-14);
  tests::check("lower_triangle(full) == lower",
               sparse::lower_triangle(full).row_index == lower.row_index &&
                 sparse::lower_triangle(full).values == lower.values);

  const sparse::CSRMatrix csr = sparse::to_csr(full);
  std::vector<double>     y_csr(30);
  csr.vmult(x.data(), y_csr.data());
  tests::check_below("CSR product", max_difference(y, y_csr), 1e-14);
  const sparse::CSCMatrix back = sparse::to_csc(csr);
  tests::check("CSC -> CSR -> CSC is the identity",
               back.column_start == full.column_start && back.row_index == full.row_index &&
                 back.values == full.values);

  const sparse::BSCMatrix bsc = sparse::to_bsc(full);
  std::cout << "BSC: " << bsc.n_block_rows << "x" << bsc.n_block_cols << " blocks of 3x3, "
            << bsc.n_blocks() << " stored blocks" << std::endl;
  std::vector<double> y_bsc(30);
  bsc.vmult(x.data(), y_bsc.data());
  tests::check_below("BSC product", max_difference(y, y_bsc), 1e-14);
  tests::check("CSC -> BSC -> CSC represents the same matrix",
               sparse::relative_difference(full, sparse::to_csc(bsc)) == 0.);
  tests::expect_error("BSC of a 4x4 matrix", [] { sparse::to_bsc(tests::random_spd(4, 1, 1)); });

  // Matrix Market round trip: 17 digits give the same doubles back.
  sparse::write_matrix_market(lower, "round_trip.mtx");
  const sparse::CSCMatrix read = sparse::read_matrix_market("round_trip.mtx");
  tests::check("Matrix Market round trip (symmetric) is bit exact",
               read.storage == sparse::Storage::lower && read.row_index == lower.row_index &&
                 read.values == lower.values);
  sparse::write_matrix_market(full, "round_trip.mtx");
  tests::check("Matrix Market round trip (general) is bit exact",
               sparse::read_matrix_market("round_trip.mtx").values == full.values);
  std::remove("round_trip.mtx");

  // deal.II SparseMatrix -> CSC: a 5x5 pattern with the diagonal and a few couplings.
  dealii::DynamicSparsityPattern dynamic(5, 5);
  for (unsigned int i = 0; i < 5; ++i)
    dynamic.add(i, i);
  for (const auto &[i, j] : std::vector<std::pair<unsigned, unsigned>>{{0, 3}, {3, 0}, {1, 4}, {4, 1}, {2, 4}, {4, 2}})
    dynamic.add(i, j);
  dealii::SparsityPattern pattern;
  pattern.copy_from(dynamic);
  dealii::SparseMatrix<double> matrix(pattern);
  for (unsigned int i = 0; i < 5; ++i)
    matrix.set(i, i, 10. + i);
  matrix.set(0, 3, -1.);
  matrix.set(3, 0, -1.);
  matrix.set(1, 4, -2.);
  matrix.set(4, 1, -2.);
  // (2,4) and (4,2) stay explicit zeros: they belong to the pattern all the same.
  sparse::CSCMatrix csc = sparse::to_csc(matrix);
  csc.check_consistency();
  std::cout << "deal.II 5x5 matrix: " << csc.n_nonzeros() << " entries in CSC" << std::endl;
  bool same = true;
  for (unsigned int i = 0; i < 5; ++i)
    for (unsigned int j = 0; j < 5; ++j)
      same &= csc(i, j) == matrix.el(i, j);
  tests::check("every entry equals the deal.II one", same);
  matrix *= 3.;
  sparse::copy_values(matrix, csc);
  same = true;
  for (unsigned int i = 0; i < 5; ++i)
    for (unsigned int j = 0; j < 5; ++j)
      same &= csc(i, j) == matrix.el(i, j);
  tests::check("copy_values brings the new values", same);
}
