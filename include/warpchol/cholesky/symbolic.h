#pragma once

#include <warpchol/base/types.h>
#include <warpchol/sparse/csc_matrix.h>

#include <vector>

/**
 * @file
 * Symbolic analysis of a left-looking Cholesky factorization (the report's section 3.2):
 * the elimination tree and both the row and the column structure of L, computed from the
 * pattern of the permuted matrix C = P^T A P.
 */
namespace warpchol::cholesky
{
  /**
   * Everything the numeric phase needs besides the values. L is lower triangular, stored
   * by columns with the diagonal first in each column and rows sorted; its strictly lower
   * part is also indexed by rows, so that the left-looking update of column j can find
   * the columns k < j with L(j,k) != 0 and the position of L(j,k).
   */
  struct SymbolicFactorization
  {
    Index n = 0;

    /** parent[j] in the elimination tree, -1 for a root. */
    std::vector<Index> parent;
    /** A postorder of the elimination tree (the identity once the ordering is postordered). */
    std::vector<Index> postorder;
    /** Entries in each column of L, diagonal included. */
    std::vector<Index> column_counts;

    /** Column structure of L: column j holds rows row_index[column_start[j] .. column_start[j+1]). */
    std::vector<Index> column_start;
    std::vector<Index> row_index;

    /**
     * Row structure of the strictly lower part of L: row i holds the columns
     * row_column[row_start[i] .. row_start[i+1]), sorted, and row_entry[] gives, for each,
     * the position of L(i, column) in the column storage (row_index / values of L).
     */
    std::vector<Index> row_start;
    std::vector<Index> row_column;
    std::vector<Index> row_entry;

    /** nnz(L), diagonal included. */
    Index nnz_l() const;

    /** Flops of a full numeric factorization: sum over columns of count^2. */
    double flops = 0;
  };

  /**
   * Elimination tree of the matrix whose lower triangle has the pattern of @p lower
   * (lower storage). Liu's algorithm with path compression, O(nnz alpha(n)).
   */
  std::vector<Index> elimination_tree(const sparse::CSCMatrix &lower);

  /** A postorder of the forest given by @p parent (children visited in increasing order). */
  std::vector<Index> postorder_tree(const std::vector<Index> &parent);

  /**
   * Column counts of L (diagonal included) for the lower-stored matrix @p lower with
   * elimination tree @p parent and its @p postorder, without forming L: the skeleton-matrix
   * algorithm of Gilbert, Ng and Peyton (as CSparse's cs_counts), O(nnz(A) alpha(n)).
   */
  std::vector<Index> column_counts(const sparse::CSCMatrix &lower, const std::vector<Index> &parent,
                                   const std::vector<Index> &postorder);

  /**
   * The report's left-looking symbolic factorization of the lower-stored matrix @p lower:
   * for k = 0..n-1, walk the upper part of column k of C (= row k of its lower triangle)
   * up the elimination tree to get the structure of row k of L and the parents it
   * decides; then merge the lower part of column k of C with the columns of the children
   * of k to get the structure of column k of L.
   */
  SymbolicFactorization analyze_left_looking(const sparse::CSCMatrix &lower);
} // namespace warpchol::cholesky
