#include <warpchol/cholesky/partial.h>

#include <algorithm>
#include <numeric>

namespace warpchol::cholesky
{
  std::vector<Index> etree_closure(const std::vector<Index> &parent,
                                   const std::vector<Index> &changed_columns)
  {
    std::vector<bool>  marked(parent.size(), false);
    std::vector<Index> closure;
    // Climb from each changed column until a column already in the closure (whose path to
    // the root is in it too) or past the root.
    for (Index j : changed_columns)
      for (; j != -1 && !marked[j]; j = parent[j])
        {
          marked[j] = true;
          closure.push_back(j);
        }
    std::sort(closure.begin(), closure.end());
    return closure;
  }

  DirtySupernodes dirty_supernodes(const SupernodalSymbolic &symbolic, const std::vector<Index> &columns)
  {
    DirtySupernodes dirty;
    for (const Index j : columns)
      {
        const Index s = symbolic.supernode_of[j];
        if (dirty.supernodes.empty() || dirty.supernodes.back() != s)
          {
            const Index offset = j - symbolic.first_column[s];
            dirty.supernodes.push_back(s);
            dirty.start_offsets.push_back(offset);
            dirty.n_columns += symbolic.first_column[s + 1] - j;
            dirty.flops += symbolic.flops_from(s, offset);
          }
      }
    return dirty;
  }

  std::vector<bool> top_supernodes(const SupernodalSymbolic &symbolic, const double flops_fraction)
  {
    const Index         ns = symbolic.n_supernodes();
    std::vector<double> subtree_flops(symbolic.supernode_flops);
    for (Index s = 0; s < ns; ++s) // children before parents
      if (symbolic.supernode_parent[s] != -1)
        subtree_flops[symbolic.supernode_parent[s]] += subtree_flops[s];
    std::vector<Index> order(ns);
    std::iota(order.begin(), order.end(), Index(0));
    std::sort(order.begin(), order.end(), [&](const Index a, const Index b) {
      return subtree_flops[a] != subtree_flops[b] ? subtree_flops[a] > subtree_flops[b] : a > b;
    });
    std::vector<bool> top(ns, flops_fraction >= 1.); // all of them, whatever the rounding of the sums
    const double      target = flops_fraction * symbolic.flops;
    double            taken  = 0;
    for (std::size_t k = 0; k < order.size() && taken < target; ++k)
      {
        top[order[k]] = true;
        taken += symbolic.supernode_flops[order[k]];
      }
    return top;
  }
} // namespace warpchol::cholesky
