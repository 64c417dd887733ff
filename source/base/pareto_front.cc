#include <warpchol/base/exceptions.h>
#include <warpchol/base/pareto_front.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace warpchol
{
  std::vector<unsigned int> pareto_front(const std::vector<double> &costs,
                                         const std::vector<double> &errors)
  {
    if (costs.size() != errors.size())
      throw Error("pareto_front: " + std::to_string(costs.size()) + " costs but " +
                  std::to_string(errors.size()) + " errors");
    std::vector<unsigned int> by_cost;
    for (unsigned int i = 0; i < costs.size(); ++i)
      if (!std::isnan(costs[i]) && !std::isnan(errors[i]))
        by_cost.push_back(i);
    // By cost, then error, then index: walking this order, a point is on the front when it
    // is more accurate than every point before it (those are at least as fast).
    std::sort(by_cost.begin(), by_cost.end(), [&](const unsigned int a, const unsigned int b) {
      if (costs[a] != costs[b])
        return costs[a] < costs[b];
      if (errors[a] != errors[b])
        return errors[a] < errors[b];
      return a < b;
    });
    std::vector<unsigned int> front;
    double                    best_error = std::numeric_limits<double>::infinity();
    for (const unsigned int i : by_cost)
      if (errors[i] < best_error || (front.empty() && errors[i] == best_error))
        {
          front.push_back(i);
          best_error = errors[i];
        }
    return front;
  }
} // namespace warpchol
