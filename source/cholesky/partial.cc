#include <warpchol/cholesky/partial.h>

#include <algorithm>

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
} // namespace warpchol::cholesky
