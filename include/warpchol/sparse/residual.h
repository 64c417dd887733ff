#pragma once

#include <warpchol/sparse/csc_matrix.h>

#include <vector>

/**
 * @file
 * Accuracy measures of a computed solution of A x = b, and how two matrices differ.
 */
namespace warpchol::sparse
{
  /** ||A x - b||_2 / ||b||_2 (||A x - b||_2 when b = 0). */
  double relative_residual(const CSCMatrix &matrix, const std::vector<double> &x,
                           const std::vector<double> &b);

  /**
   * Normwise backward error ||A x - b||_inf / (||A||_inf ||x||_inf + ||b||_inf): the
   * smallest relative perturbation of A and b for which x is an exact solution.
   */
  double backward_error(const CSCMatrix &matrix, const std::vector<double> &x,
                        const std::vector<double> &b);

  /**
   * ||a - b||_F / ||a||_F over the union of both patterns (entries missing on one side
   * count as zero): how far two factors or matrices of the same size are apart.
   */
  double relative_difference(const CSCMatrix &a, const CSCMatrix &b);

  /**
   * The columns (sorted) where a stored value of @p b differs from @p a's, both of the same
   * pattern (MatrixError otherwise): a complete listing of the change for
   * SparseCholesky::refactorize().
   */
  std::vector<Index> changed_columns(const CSCMatrix &a, const CSCMatrix &b);
} // namespace warpchol::sparse
