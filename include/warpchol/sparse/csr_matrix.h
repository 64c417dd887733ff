#pragma once

#include <warpchol/base/types.h>

#include <vector>

/**
 * @file
 * Compressed Sparse Row storage.
 */
namespace warpchol::sparse
{
  /**
   * A sparse matrix in Compressed Sparse Row form: the entries of row i are
   * column_index[k], values[k] for k in [row_start[i], row_start[i+1]), columns sorted.
   */
  struct CSRMatrix
  {
    Index               n_rows = 0;
    Index               n_cols = 0;
    std::vector<Index>  row_start{0};
    std::vector<Index>  column_index;
    std::vector<double> values;

    /** Number of stored entries. */
    Index n_nonzeros() const;

    /** y = A x. */
    void vmult(const double *x, double *y) const;
  };
} // namespace warpchol::sparse
