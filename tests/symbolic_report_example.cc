// The left-looking symbolic and numeric factorization on the 9x9 example of the seed
// report (section 3.2-3.3, figures 4-5 and the numeric walk-through): elimination tree,
// row structure (L_rowptr, L_colind), column structure (L_colptr, L_rowind) and L, in the
// natural order as the report shows them; L is checked against a dense Cholesky factor.

#include <warpchol/cholesky/numeric_simplicial.h>
#include <warpchol/cholesky/partial.h>
#include <warpchol/cholesky/symbolic.h>

#include "tests.h"

#include <cstdio>

using namespace warpchol;

namespace
{
  sparse::CSCMatrix report_matrix()
  {
    // Lower triangle of the report's figure 4, column by column (0-based).
    const Index n = 9;
    const std::vector<std::vector<std::pair<Index, double>>> columns = {
      {{0, 21}, {2, 4}, {4, 8}, {5, 8}},
      {{1, 45}, {3, 24}, {7, 18}, {8, 12}},
      {{2, 21}, {3, 10}, {5, 2}},
      {{3, 41}, {7, 12}, {8, 8}},
      {{4, 65}, {6, 1}},
      {{5, 4}},
      {{6, 1}},
      {{7, 10}, {8, 6}},
      {{8, 4}}};
    sparse::CSCMatrix matrix = sparse::CSCMatrix::zero(n, n, sparse::Storage::lower);
    for (Index j = 0; j < n; ++j)
      {
        for (const auto &[i, value] : columns[j])
          {
            matrix.row_index.push_back(i);
            matrix.values.push_back(value);
          }
        matrix.column_start[j + 1] = static_cast<Index>(matrix.row_index.size());
      }
    return matrix;
  }

  void print_array(const std::string &name, const std::vector<Index> &values)
  {
    std::cout << name << " = [";
    for (const Index v : values)
      std::cout << ' ' << v;
    std::cout << " ]" << std::endl;
  }
} // namespace

int main()
{
  const sparse::CSCMatrix               a        = report_matrix();
  const cholesky::SymbolicFactorization symbolic = cholesky::analyze_left_looking(a);

  print_array("parent", symbolic.parent);
  print_array("L_rowptr", symbolic.row_start);
  print_array("L_colind", symbolic.row_column);
  print_array("L_colptr", symbolic.column_start);
  print_array("L_rowind", symbolic.row_index);
  print_array("column counts", symbolic.column_counts);
  print_array("postorder", symbolic.postorder);
  std::cout << "nnz(L) = " << symbolic.nnz_l() << ", flops = " << symbolic.flops << std::endl;

  std::vector<double> left, up;
  cholesky::factorize_left_looking(symbolic, a, {}, left);
  cholesky::factorize_up_looking(symbolic, a, up);

  // L, dense, 3 decimals (the report's walk-through shows 4.583, 0.873, 4.499, -0.339, ...).
  const Index         n = symbolic.n;
  std::vector<double> l_dense(n * n, 0.);
  for (Index j = 0; j < n; ++j)
    for (Index p = symbolic.column_start[j]; p < symbolic.column_start[j + 1]; ++p)
      l_dense[symbolic.row_index[p] + j * n] = left[p];
  std::cout << "L =" << std::endl;
  for (Index i = 0; i < n; ++i)
    {
      for (Index j = 0; j <= i; ++j)
        // Entries that round to zero print as 0.000, never -0.000.
        std::printf("%8.3f", std::abs(l_dense[i + j * n]) < 5e-4 ? 0. : l_dense[i + j * n]);
      std::printf("\n");
    }
  std::fflush(stdout);

  const std::vector<double> reference = tests::dense_cholesky(tests::to_dense(a), n);
  double difference = 0, norm = 0, up_difference = 0;
  for (Index k = 0; k < n * n; ++k)
    {
      difference += (l_dense[k] - reference[k]) * (l_dense[k] - reference[k]);
      norm += reference[k] * reference[k];
    }
  for (std::size_t p = 0; p < left.size(); ++p)
    up_difference += (left[p] - up[p]) * (left[p] - up[p]);
  tests::check_below("left-looking L vs dense Cholesky (relative)", std::sqrt(difference / norm), 1e-14);
  tests::check_below("left-looking L vs up-looking L (relative)", std::sqrt(up_difference / norm), 1e-14);

  // The report's partial refactorization: change column 2, recompute its path to the root.
  print_array("etree closure of {2}", cholesky::etree_closure(symbolic.parent, {2}));
  print_array("etree closure of {6}", cholesky::etree_closure(symbolic.parent, {6}));
  print_array("etree closure of {0, 4}", cholesky::etree_closure(symbolic.parent, {0, 4}));
}
