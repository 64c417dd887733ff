#pragma once

#include <warpchol/base/types.h>

#include <vector>

/**
 * @file
 * Which columns a partial refactorization must recompute (CHOLMOD's "modify" concern).
 *
 * Column j of L depends on the entries of C = P^T A P in the columns of its subtree of
 * the elimination tree (j and its descendants), and on nothing else. So when the columns
 * S of C change, exactly the columns on the paths from S to the roots must be
 * recomputed; every other column of L keeps its values, bit for bit.
 */
namespace warpchol::cholesky
{
  /**
   * The union of the elimination-tree paths from each of @p changed_columns (permuted
   * numbering) to its root, sorted increasingly. O(size of the result + |changed|).
   */
  std::vector<Index> etree_closure(const std::vector<Index> &parent,
                                   const std::vector<Index> &changed_columns);
} // namespace warpchol::cholesky
