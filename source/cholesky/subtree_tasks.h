#pragma once

#include <warpchol/base/types.h>
#include <warpchol/cholesky/supernodal_symbolic.h>

#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <vector>

/**
 * @file
 * (Private to the solver.) How the supernodal codes that walk a set of supernodes children
 * first (the numeric factorization, the update and downdate) spread them over threads:
 * independent subtrees side by side, the supernodes where they join after them.
 */
namespace warpchol::cholesky
{
  /**
   * Run compute(s, joined) on each supernode of @p listed (sorted increasingly, so children
   * before parents; with s, the parent of s if it is listed at all must come later, which
   * every upward-closed set satisfies), each after the listed supernodes of its subtree.
   *
   * On one thread, in the order of @p listed. On @p n_threads threads, a subtree whose
   * weight (the sum of @p weight over its listed supernodes) is at most an eighth of a
   * thread's share runs as one task in order; above it, its listed children run as tasks
   * of their own, then the supernode itself with joined = true: a supernode where heavy
   * subtrees meet, whose own work compute() may split over threads. @p is_listed(s) tells
   * whether s is in @p listed.
   */
  template <typename IsListed, typename Weight, typename Compute>
  void for_each_supernode_bottom_up(const SupernodalSymbolic &symbolic, const std::vector<Index> &listed,
                                    const unsigned int n_threads, const IsListed &is_listed, const Weight &weight,
                                    const Compute &compute)
  {
    if (n_threads <= 1)
      {
        for (const Index s : listed)
          compute(s, false);
        return;
      }
    const Index         ns = symbolic.n_supernodes();
    std::vector<Index>  child_start(ns + 1, 0), roots;
    std::vector<double> subtree_weight(ns, 0.);
    for (const Index s : listed)
      {
        const Index p = symbolic.supernode_parent[s];
        if (p != -1 && is_listed(p))
          ++child_start[p + 1];
        else
          roots.push_back(s);
      }
    for (Index s = 0; s < ns; ++s)
      child_start[s + 1] += child_start[s];
    std::vector<Index> children(child_start[ns]);
    std::vector<Index> next(child_start.begin(), child_start.end() - 1);
    double             total = 0;
    for (const Index s : listed)
      {
        subtree_weight[s] += weight(s);
        total += weight(s);
        const Index p = symbolic.supernode_parent[s];
        if (p != -1 && is_listed(p))
          {
            children[next[p]++] = s;
            subtree_weight[p] += subtree_weight[s];
          }
      }
    // Subtrees below this weight run as one sequential task: enough tasks to balance the
    // threads, not so many that scheduling costs show.
    const double sequential_cutoff = total / (8. * n_threads);

    const auto run_subtree = [&](const auto &self, const Index s) -> void {
      if (subtree_weight[s] <= sequential_cutoff)
        {
          // The subtree of s is the range [first_descendant[s], s] of supernodes.
          const auto first = std::lower_bound(listed.begin(), listed.end(), symbolic.first_descendant[s]);
          const auto last  = std::upper_bound(first, listed.end(), s);
          for (auto t = first; t != last; ++t)
            compute(*t, false);
          return;
        }
      tbb::task_group group;
      for (Index k = child_start[s]; k < child_start[s + 1]; ++k)
        {
          const Index child = children[k];
          group.run([&self, child] { self(self, child); });
        }
      // A cancelled group (another subtree threw) returns without running all the
      // children: s must not run then, its children's results are missing.
      if (group.wait() != tbb::task_group_status::complete)
        return;
      compute(s, true);
    };
    tbb::task_arena arena(static_cast<int>(n_threads));
    arena.execute([&] {
      tbb::task_group group;
      for (const Index root : roots)
        group.run([&run_subtree, root] { run_subtree(run_subtree, root); });
      group.wait();
    });
  }
} // namespace warpchol::cholesky
