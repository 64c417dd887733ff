#pragma once

#include <warpchol/sparse/csc_matrix.h>

#include <deal.II/lac/sparse_matrix.h>

/**
 * @file
 * From deal.II's matrices to the solver's formats.
 */
namespace warpchol::sparse
{
  /**
   * The CSC form (full storage) of a deal.II SparseMatrix: every entry of its sparsity
   * pattern is kept, explicit zeros included, so the pattern does not depend on values
   * and stays fixed from one assembly to the next.
   */
  CSCMatrix to_csc(const dealii::SparseMatrix<double> &matrix);

  /**
   * Copy the values of @p matrix into @p csc, which came from to_csc() of a matrix with
   * the same sparsity pattern: O(nnz), no allocation.
   */
  void copy_values(const dealii::SparseMatrix<double> &matrix, CSCMatrix &csc);
} // namespace warpchol::sparse
