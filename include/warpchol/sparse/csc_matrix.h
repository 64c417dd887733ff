#pragma once

#include <warpchol/base/types.h>

#include <cmath>
#include <vector>

/**
 * @file
 * Compressed Sparse Column storage, the format the Cholesky solver works on.
 */
namespace warpchol::sparse
{
  /** Which entries of a matrix are stored. */
  enum class Storage
  {
    /** Every nonzero entry is stored (symmetric or not). */
    full,
    /** A symmetric matrix of which only the lower triangle (i >= j) is stored. */
    lower
  };

  /**
   * A sparse matrix in Compressed Sparse Column form: the entries of column j are
   * row_index[k], values[k] for k in [column_start[j], column_start[j+1]). Row indices
   * are sorted and unique within a column (check_consistency() verifies it).
   */
  struct CSCMatrix
  {
    Index               n_rows = 0;
    Index               n_cols = 0;
    std::vector<Index>  column_start{0};
    std::vector<Index>  row_index;
    std::vector<double> values;
    Storage             storage = Storage::full;

    /** An empty matrix with the given size and no stored entry. */
    static CSCMatrix zero(Index n_rows, Index n_cols, Storage storage = Storage::full);

    /** Number of stored entries. */
    Index n_nonzeros() const;

    /** A(i,j), or 0 where the entry is not stored; honours lower storage. O(log nnz(col)). */
    double operator()(Index i, Index j) const;

    /** y = A x (a symmetric product when only the lower triangle is stored). */
    void vmult(const double *x, double *y) const;

    /**
     * Throw MatrixError unless the arrays describe a valid matrix: sizes agree, column
     * starts are non-decreasing, row indices are in range, sorted and unique, and with
     * lower storage no entry lies above the diagonal.
     */
    void check_consistency() const;
  };

  /**
   * Whether A(i,j) = @p value and A(j,i) = @p twin agree as the entries of a symmetric
   * matrix: @p twin finite and within 1e-10 sqrt(|A(i,i)| |A(j,j)|) of @p value (the
   * diagonal entries @p diagonal_i and @p diagonal_j). The solver's test, and that of the
   * programs that read a matrix to factor.
   */
  inline bool symmetric_pair(const double value, const double twin, const double diagonal_i,
                             const double diagonal_j)
  {
    return std::isfinite(twin) &&
           std::abs(value - twin) <= 1e-10 * std::sqrt(std::abs(diagonal_i) * std::abs(diagonal_j));
  }
} // namespace warpchol::sparse
