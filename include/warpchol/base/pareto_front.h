#pragma once

#include <vector>

/**
 * @file
 * The Pareto front of a trade-off between two costs (here: run time and error).
 */
namespace warpchol
{
  /**
   * The indices of the points that no other point dominates, by increasing @p costs (and
   * so decreasing @p errors): point i is dominated when some j has costs[j] <= costs[i] and
   * errors[j] <= errors[i], one of them strictly, i.e. j is at least as fast and as accurate
   * and better in one. Of points equal in both, the first is on the front; a point with a
   * NaN is on none. @p costs and @p errors have the same size.
   */
  std::vector<unsigned int> pareto_front(const std::vector<double> &costs,
                                         const std::vector<double> &errors);
} // namespace warpchol
