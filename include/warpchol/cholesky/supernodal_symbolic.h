#pragma once

#include <warpchol/base/types.h>
#include <warpchol/sparse/csc_matrix.h>

#include <vector>

/**
 * @file
 * Supernodal symbolic analysis (CHOLMOD's cholmod_super_symbolic concern): fundamental
 * supernodes, relaxed amalgamation, the supernodal elimination tree, the row structure of
 * each supernode, and, for the left-looking numeric phase and its partial variant, the
 * list of descendant supernodes that update each supernode.
 */
namespace warpchol::cholesky
{
  /**
   * Relaxed amalgamation: a supernode is merged with its parent when the merged supernode
   * has at most nrelax[0] columns, or at most nrelax[1] columns and a fraction of explicit
   * zeros below zrelax[0], or at most nrelax[2] columns and zeros below zrelax[1], or zeros
   * below zrelax[2]. CHOLMOD's defaults. Fewer, larger supernodes cost some zeros but make
   * BLAS calls longer and fewer.
   */
  struct SupernodeRelaxation
  {
    bool   enabled   = true;
    Index  nrelax[3] = {4, 16, 48};
    double zrelax[3] = {0.8, 0.1, 0.05};
  };

  /**
   * The structure of a supernodal factor of C = P^T A P (P postordered). Supernode s holds
   * the columns [first_column[s], first_column[s+1]) of L as one dense column-major block
   * of n_rows(s) x n_columns(s) values starting at value_start[s]; its rows are
   * row_index[row_start[s] ..): first its own columns, then the rows below, sorted.
   */
  struct SupernodalSymbolic
  {
    Index n = 0;

    /** Column elimination tree and exact column counts of L (diagonal included). */
    std::vector<Index> parent;
    std::vector<Index> column_counts;

    std::vector<Index> first_column;
    std::vector<Index> supernode_of;
    /** Parent in the supernodal elimination tree, -1 for a root. */
    std::vector<Index> supernode_parent;
    /** First supernode of the subtree rooted at s: that subtree is [first_descendant[s], s]. */
    std::vector<Index> first_descendant;

    std::vector<Index> row_start;
    std::vector<Index> row_index;
    std::vector<Index> value_start;

    /**
     * Updates into supernode s, in increasing order of the descendant: update k in
     * [update_start[s], update_start[s+1]) comes from supernode update_source[k], whose rows
     * row_index[update_row_begin[k] .. update_row_end[k]) are columns of s and whose rows
     * from update_row_begin[k] to its last one are the rows of the update.
     */
    std::vector<Index> update_start;
    std::vector<Index> update_source;
    std::vector<Index> update_row_begin;
    std::vector<Index> update_row_end;

    /** Flops of computing supernode s (its updates, dense Cholesky and triangular solve). */
    std::vector<double> supernode_flops;
    /** Sum of supernode_flops (padding zeros included). */
    double flops = 0;
    /** Sum of squared column counts: the flops of an unpadded factorization (CHOLMOD's fl). */
    double exact_flops = 0;
    /** Largest rows x columns product of an update: the size of a workspace. */
    Index max_update_size = 0;

    /**
     * First position of update k (into supernode s) whose row is at or after column
     * first_column[s] + q: where the update starts when s is recomputed from its local
     * column q on.
     */
    Index update_first_row(Index k, Index s, Index q) const;

    /**
     * Flops of computing supernode s from its local column q on: the updates from its
     * descendants restricted to those columns, the update by its own columns [0, q),
     * dpotrf and dtrsm. flops_from(s, 0) = supernode_flops[s].
     */
    double flops_from(Index s, Index q) const;

    Index n_supernodes() const;
    Index n_columns(Index s) const;
    Index n_rows(Index s) const;
    /** Entries of L stored (dense blocks, padding included). */
    Index n_stored_values() const;
    /** Entries of L without padding (sum of column counts). */
    Index nnz_l() const;
  };

  /**
   * Supernodal analysis of the lower-stored permuted matrix @p lower, whose elimination
   * tree @p parent must be postordered (every subtree a contiguous range of columns).
   */
  SupernodalSymbolic analyze_supernodal(const sparse::CSCMatrix &lower,
                                        const std::vector<Index> &parent,
                                        const SupernodeRelaxation &relaxation);
} // namespace warpchol::cholesky
