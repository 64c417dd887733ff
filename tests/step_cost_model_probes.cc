// StepCostModel: a held-up iterating step does not lock auto into exact steps. Exact steps
// cost 0.3 ms; an iteration 0.07 ms and the rest of an iterating step 0.1 ms, but the first
// iterating step was held up by the machine (10 ms for its one iteration). The model then
// makes every step exact, which measures no iteration: after a run of exact steps back to
// back one step iterates (a probe), and its time, under half the average, replaces the
// held-up one. Where exact steps are right (an iterating step really costs 1 ms), the probes
// come at intervals that double, and cost a small share of a long run.

#include <warpchol/models/step_strategy.h>

#include "tests.h"

using namespace warpchol;

namespace
{
  /** Steps of a run of @p steps that the model iterates, each costing @p iterating_seconds. */
  unsigned int run(fem::StepCostModel &model, const unsigned int steps, const double iterating_seconds)
  {
    unsigned int iterating = 0, staleness = 1;
    for (unsigned int step = 0; step < steps; ++step)
      {
        const bool exact = model.exact_step_is_due(staleness);
        model.record_own_step(exact);
        if (exact)
          {
            model.record_exact_step(3e-4, staleness - 1);
            staleness = 1;
            continue;
          }
        ++iterating;
        // The iteration costs 0.07 ms, the rest of the step what is left.
        model.record_iterating_step(staleness, iterating_seconds, 1);
        model.record_iterations(cholesky::Refresh::none, 1, 7e-5);
        ++staleness;
      }
    return iterating;
  }

  fem::StepCostModel held_up_model()
  {
    fem::StepCostModel model;
    model.record_setup(1e-3, 5e-4);
    model.record_iterations(cholesky::Refresh::all, 1, 1e-2);
    model.record_iterating_step(1, 1.02e-2, 1);
    model.record_exact_step(3e-4, 0);
    return model;
  }
} // namespace

int main()
{
  fem::StepCostModel model = held_up_model();
  std::cout << "after a held-up iterating step: " << 1e3 * model.predicted_iterating_seconds(1)
            << " ms predicted for an iterating step, " << 1e3 * model.predicted_exact_seconds()
            << " ms for an exact one" << std::endl;
  tests::check("  an exact step is due right after an exact step", model.exact_step_is_due(1));
  unsigned int exact_before_probe = 0;
  while (model.exact_step_is_due(1) && exact_before_probe < 100)
    {
      model.record_own_step(true);
      model.record_exact_step(3e-4, 0);
      ++exact_before_probe;
    }
  std::cout << "exact steps back to back before a probe: " << exact_before_probe << std::endl;
  tests::check("  the probe comes", exact_before_probe > 0 && exact_before_probe < 100);
  model.record_own_step(false);
  model.record_iterating_step(1, 1.7e-4, 1);
  model.record_iterations(cholesky::Refresh::none, 1, 7e-5);
  std::cout << "after the probe: " << 1e3 * model.predicted_iterating_seconds(1) << " ms predicted" << std::endl;
  tests::check("  the probe's time replaces the held-up one", model.predicted_iterating_seconds(1) < 3e-4);
  tests::check("  the next step iterates", !model.exact_step_is_due(1));

  // A run of 1000 steps from the held-up start: iterating steps of 0.17 ms are found and kept.
  fem::StepCostModel cheap = held_up_model();
  const unsigned int iterated_cheap = run(cheap, 1000, 1.7e-4);
  std::cout << "iterating steps of 0.17 ms: " << iterated_cheap << " of 1000 steps iterate" << std::endl;
  tests::check("  nearly all", iterated_cheap > 900);

  // Iterating steps that do cost 1 ms: the probes only, ever rarer.
  fem::StepCostModel dear = held_up_model();
  const unsigned int iterated_dear = run(dear, 1000, 1e-3);
  std::cout << "iterating steps of 1 ms: " << iterated_dear << " of 1000 steps iterate (the probes)" << std::endl;
  tests::check("  a probe at 8, 16, 32, ... exact steps: at most 8 in 1000 steps",
               iterated_dear > 0 && iterated_dear <= 8);
}
