// The Pareto front of the error-against-time study: the configurations that no other one
// beats in both time and error, by increasing time; ties, NaNs, one point, none.

#include "tests.h"

#include <warpchol/base/pareto_front.h>

#include <limits>

using namespace warpchol;

namespace
{
  void print_front(const std::string &label, const std::vector<double> &seconds,
                   const std::vector<double> &errors)
  {
    std::cout << label << ":";
    for (const unsigned int i : pareto_front(seconds, errors))
      std::cout << " " << i;
    std::cout << std::endl;
  }
} // namespace

int main()
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();

  // A sweep as the study's: 0 the exact run (slow, error 0), 1-3 a faster, less accurate
  // trade-off, 4 slower and worse than 2, 5 as fast as 3 but worse.
  print_front("sweep (expect 3 2 1 0)", {0.036, 0.030, 0.020, 0.010, 0.025, 0.010},
              {0, 1e-3, 1e-2, 5e-2, 2e-2, 6e-2});
  print_front("equal in both: the first (expect 1 0)", {2, 1, 1}, {0, 1, 1});
  print_front("equal time: the more accurate (expect 2 0)", {2, 1, 1}, {0, 1, 0.5});
  print_front("equal error: the faster (expect 1)", {2, 1}, {1, 1});
  print_front("NaN on no front (expect 1)", {nan, 1, 0.5}, {0, 1, nan});
  print_front("infinite error, fastest (expect 1 0)", {2, 1}, {0, inf});
  print_front("one point (expect 0)", {3}, {4});
  print_front("none (expect nothing)", {}, {});
  tests::expect_error("sizes differ", [] { pareto_front({1, 2}, {1}); });
}
