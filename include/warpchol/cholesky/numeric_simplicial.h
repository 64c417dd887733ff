#pragma once

#include <warpchol/base/types.h>
#include <warpchol/cholesky/symbolic.h>
#include <warpchol/sparse/csc_matrix.h>

#include <vector>

/**
 * @file
 * Column-by-column numeric factorizations: the left-looking one (the report's section
 * 3.3), which can recompute any subset of columns closed under elimination-tree ancestry,
 * and the up-looking one of CSparse's cs_chol, kept as the report's baseline.
 */
namespace warpchol::cholesky
{
  /**
   * Left-looking numeric factorization of the lower-stored matrix @p lower into
   * @p l_values (stored on the structure of @p symbolic). For each column j in
   * @p columns, in increasing order:
   *
   *     c = C(j:n, j);  for each k < j with L(j,k) != 0:  c -= L(j:n, k) L(j,k)
   *     L(j,j) = sqrt(c_0);  L(j+1:n, j) = c_1.. / L(j,j)
   *
   * Every column a listed column depends on must be listed too or be valid in
   * @p l_values already (partial refactorization lists an ancestor-closed set). An empty
   * @p columns means all columns. Returns the flops spent; throws NotPositiveDefinite
   * with the (permuted) column whose pivot is not positive.
   */
  double factorize_left_looking(const SymbolicFactorization &symbolic,
                                const sparse::CSCMatrix     &lower,
                                const std::vector<Index>    &columns,
                                std::vector<double>         &l_values);

  /** The flops factorize_left_looking() spends on column @p j (permuted numbering). */
  double left_looking_column_flops(const SymbolicFactorization &symbolic, Index j);

  /**
   * Up-looking numeric factorization (CSparse's cs_chol): row k of L by a sparse
   * triangular solve with the rows above it, the row pattern found by walking the
   * elimination tree. Fills @p l_values on the same structure as the left-looking one.
   */
  void factorize_up_looking(const SymbolicFactorization &symbolic,
                            const sparse::CSCMatrix     &lower,
                            std::vector<double>         &l_values);
} // namespace warpchol::cholesky
