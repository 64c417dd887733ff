// The rates that choose between updating the factor and recomputing its columns
// (cholesky::RefactorizationCostModel). An update streams L at low rank: for the same
// flops, rank 1 is predicted k/(k + 2.5) slower than a rank where its kernels run at their
// rate, before any measurement and after. One measured update at rank 1 predicts its own
// seconds again, and less at rank 64 for the same flops. A recomputation's rate ignores the
// rank. A measured factorization sets the update's prior, measured updates follow their
// own rate, and a saved model loads to the same predictions. Fixed rates (Change method =
// flops) learn nothing and depend on neither rank nor SIMD target.

#include <warpchol/base/binary_io.h>
#include <warpchol/cholesky/refactorization_choice.h>

#include <cmath>
#include <sstream>

#include "tests.h"

using namespace warpchol;
using cholesky::RefactorizationCostModel;
using cholesky::RefactorizationMethod;

namespace
{
  bool close(const double a, const double b)
  {
    return std::abs(a - b) <= 1e-12 * std::abs(b);
  }

  /** The ratio of the seconds predicted at rank 1 to those at rank 64, for the same flops. */
  double low_rank_slowdown(const RefactorizationCostModel &model)
  {
    return model.predicted_seconds(RefactorizationMethod::update, 1e8, 1) /
           model.predicted_seconds(RefactorizationMethod::update, 1e8, 64);
  }
} // namespace

int main()
{
  const double expected_slowdown = (64 / 66.5) / (1 / 3.5);
  {
    RefactorizationCostModel model;
    std::cout << "before any measurement:" << std::endl;
    tests::check("  rank 1 predicted (64/66.5)/(1/3.5) times as slow as rank 64",
                 close(low_rank_slowdown(model), expected_slowdown));
    tests::check("  a partial refactorization's prediction ignores the rank",
                 model.predicted_seconds(RefactorizationMethod::partial, 1e8, 1) ==
                   model.predicted_seconds(RefactorizationMethod::partial, 1e8, 64));

    // A factorization at 1e10 flop/s: the partial's rate, and the update's prior from it.
    const double update_before = model.predicted_seconds(RefactorizationMethod::update, 1e8, 16);
    model.record(RefactorizationMethod::full, 1e9, 0.1);
    std::cout << "a full factorization measured at 1e10 flop/s:" << std::endl;
    tests::check("  the partial refactorization predicted at its rate",
                 close(model.predicted_seconds(RefactorizationMethod::partial, 1e9), 0.1));
    const double update_after = model.predicted_seconds(RefactorizationMethod::update, 1e8, 16);
    tests::check("  the update's prior follows it (default 2e10: twice as slow now)",
                 close(update_after / update_before, 2.));

    model.record(RefactorizationMethod::update, 2e7, 0.004, 1);
    std::cout << "an update of rank 1 measured:" << std::endl;
    tests::check("  the same update predicted at its measured seconds",
                 close(model.predicted_seconds(RefactorizationMethod::update, 2e7, 1), 0.004));
    tests::check("  rank 64, same flops, predicted faster by the same ratio",
                 close(low_rank_slowdown(model), expected_slowdown));
    tests::check("  the factorization's rate is untouched",
                 close(model.predicted_seconds(RefactorizationMethod::partial, 1e9), 0.1));

    // A second measurement moves the rate part of the way (a moving average).
    model.record(RefactorizationMethod::update, 2e7, 0.002, 1);
    const double next = model.predicted_seconds(RefactorizationMethod::update, 2e7, 1);
    tests::check("  a faster second update moves the prediction between the two", next > 0.002 && next < 0.004);

    std::ostringstream stream;
    {
      BinaryWriter writer(stream);
      model.save(writer);
    }
    RefactorizationCostModel loaded;
    const std::string        bytes = stream.str();
    std::istringstream       input(bytes);
    BinaryReader             reader(input, "cost model", bytes.size());
    loaded.load(reader);
    std::cout << "saved and loaded:" << std::endl;
    tests::check("  the same predictions",
                 loaded.predicted_seconds(RefactorizationMethod::update, 3e7, 7) ==
                     model.predicted_seconds(RefactorizationMethod::update, 3e7, 7) &&
                   loaded.predicted_seconds(RefactorizationMethod::partial, 3e7) ==
                     model.predicted_seconds(RefactorizationMethod::partial, 3e7));
  }
  {
    RefactorizationCostModel fixed(true);
    const double             before = fixed.predicted_seconds(RefactorizationMethod::update, 1e8, 3);
    fixed.record(RefactorizationMethod::update, 1e8, 1., 3);
    fixed.record(RefactorizationMethod::full, 1e9, 1.);
    std::cout << "fixed rates:" << std::endl;
    tests::check("  nothing measured changes a prediction",
                 fixed.predicted_seconds(RefactorizationMethod::update, 1e8, 3) == before);
    tests::check("  the factorization's rate is known", fixed.knows_factorization_rate());
    tests::check("  an update's prediction depends on neither rank nor target (half the default rate)",
                 fixed.predicted_seconds(RefactorizationMethod::update, 1e8, 1) ==
                     fixed.predicted_seconds(RefactorizationMethod::update, 1e8, 64) &&
                   close(fixed.predicted_seconds(RefactorizationMethod::update, 1e8, 1), 1e8 / 1e10));
  }
}
