#pragma once

#include <warpchol/sparse/bsc_matrix.h>
#include <warpchol/sparse/csc_matrix.h>
#include <warpchol/sparse/csr_matrix.h>

/**
 * @file
 * Conversions between the sparse formats. Every conversion keeps the represented matrix;
 * row or column indices come out sorted.
 */
namespace warpchol::sparse
{
  /** The transpose, with full storage (a lower-stored matrix is symmetric: expanded). */
  CSCMatrix transpose(const CSCMatrix &matrix);

  /** CSC to CSR (the represented matrix: lower storage is expanded first). */
  CSRMatrix to_csr(const CSCMatrix &matrix);

  /** CSR to CSC with full storage. */
  CSCMatrix to_csc(const CSRMatrix &matrix);

  /**
   * CSC to BSC with 3x3 blocks; the size must be a multiple of 3. Entries that are not
   * stored in a block that holds some stored entry become explicit zeros.
   */
  BSCMatrix to_bsc(const CSCMatrix &matrix);

  /** BSC to CSC with full storage; every entry of every stored block is kept. */
  CSCMatrix to_csc(const BSCMatrix &matrix);

  /** Both triangles of a symmetric matrix stored with lower storage (full stays full). */
  CSCMatrix to_full_storage(const CSCMatrix &matrix);

  /**
   * The upper triangle by columns of a symmetric matrix given by its lower triangle: column
   * k lists the entries of row k of @p lower (the entries left of the diagonal, and the
   * diagonal). Full storage, as it is a triangular matrix.
   */
  CSCMatrix upper_triangle(const CSCMatrix &lower);

  /** The lower triangle (i >= j) of a matrix, with lower storage. */
  CSCMatrix lower_triangle(const CSCMatrix &matrix);
} // namespace warpchol::sparse
