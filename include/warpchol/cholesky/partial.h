#pragma once

#include <warpchol/base/types.h>
#include <warpchol/cholesky/supernodal_symbolic.h>

#include <vector>

/**
 * @file
 * Which columns a partial refactorization must recompute: the paths from the changed columns
 * to the roots (CHOLMOD has no such module; its Modify module, our modify.h, updates the
 * factor instead).
 *
 * Column j of L depends on the entries of C = P^T A P in the columns of its subtree of
 * the elimination tree (j and its descendants), and on nothing else. So when the columns
 * S of C change, exactly the columns on the paths from S to the roots must be
 * recomputed; every other column of L keeps its values, bit for bit.
 *
 * The same holds for supernodes, computed left-looking: supernode s reads only the columns
 * of C in its subtree and the supernodes below it. So a supernode below an upward-closed
 * set of supernodes (the "top") never depends on one in it, and the top can be left stale
 * while everything below it is brought up to date.
 */
namespace warpchol::cholesky
{
  /**
   * The union of the elimination-tree paths from each of @p changed_columns (permuted
   * numbering) to its root, sorted increasingly. O(size of the result + |changed|).
   */
  std::vector<Index> etree_closure(const std::vector<Index> &parent,
                                   const std::vector<Index> &changed_columns);

  /** The supernodes that hold some of a set of columns, and what recomputing them costs. */
  struct DirtySupernodes
  {
    /** Sorted. */
    std::vector<Index> supernodes;
    /**
     * Local column of supernodes[k] from which it is recomputed: the first of the columns
     * in it, since the columns before depend on nothing that changed.
     */
    std::vector<Index> start_offsets;
    /** Columns recomputed: from each start to the end of its supernode. */
    Index              n_columns = 0;
    /** Flops of recomputing them (SupernodalSymbolic::flops_from). */
    double             flops = 0;
  };

  /** The supernodes of @p symbolic that hold some of @p columns (permuted numbering, sorted). */
  DirtySupernodes dirty_supernodes(const SupernodalSymbolic &symbolic, const std::vector<Index> &columns);

  /**
   * The top of the supernodal elimination tree: the smallest upward-closed set of
   * supernodes (with s, its parent) whose supernode_flops add up to at least
   * @p flops_fraction of all. Supernodes are taken in decreasing order of the flops of
   * their subtree, which decrease strictly down every path, so that each prefix of the
   * order is upward-closed (ties, from rounding, go to the larger index: the ancestor).
   * Returns top[s] for each supernode s.
   */
  std::vector<bool> top_supernodes(const SupernodalSymbolic &symbolic, double flops_fraction);
} // namespace warpchol::cholesky
