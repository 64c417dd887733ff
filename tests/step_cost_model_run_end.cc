// StepCostModel::exact_step_is_due(): the rule of renewal, and the run's end. A cycle
// measured as an exact step of 1 s, then iterating steps of 0.1 s and 0.02 s more per step
// of staleness (CG iterations 2, 3, 4, ...): the rule makes the step exact once the next
// step would cost more than the least average cycle. With the run's end in view, that step
// stays iterating while the steps left are too few to repay an exact step, and is exact
// again when they are many. The iterations a step may spend before it is made exact instead
// (affordable_iterations()): none known before an exact step and an iteration were
// measured, then the exact step's seconds over an iteration's, 1 / 0.02 = 50.
// Steps that also paid for a cut's refresh (record_iterations_at(): their iterations, not
// their seconds) make the exact step due where the same iterations did; their seconds,
// counted as iterating ones, would have made it due earlier.

#include <warpchol/models/step_strategy.h>

#include "tests.h"

using namespace warpchol;

namespace
{
  /** The first staleness up to 20 at which @p model makes the step exact (0: none). */
  unsigned int first_due(const fem::StepCostModel &model)
  {
    for (unsigned int s = 1; s <= 20; ++s)
      if (model.exact_step_is_due(s))
        return s;
    return 0;
  }
} // namespace

int main()
{
  fem::StepCostModel model;
  std::cout << "affordable iterations before anything was measured: " << model.affordable_iterations()
            << " (not known)" << std::endl;
  // One iteration costs 0.02 s; the rest of an iterating step 0.1 s.
  model.record_iterations(cholesky::Refresh::all, 1, 0.02);
  model.record_exact_step(1.0, 0);
  for (unsigned int s = 1; s <= 20; ++s)
    model.record_iterating_step(s, 0.1 + 0.02 * (s + 1), s + 1);
  std::cout << "affordable iterations: " << model.affordable_iterations() << std::endl;

  const unsigned int due_at = first_due(model);
  std::cout << "the run's end unknown: an exact step is due at staleness " << due_at << std::endl;
  tests::check("  not before, and within the measured cycle", due_at > 1 && due_at < 20 &&
                                                                  !model.exact_step_is_due(due_at - 1));

  // Iterating on from due_at for k steps costs sum c(due_at + j); an exact step then k - 1
  // steps 1 + sum c(j + 1).
  unsigned int least_steps_left = 0;
  for (unsigned int left = 1; left <= 64 && least_steps_left == 0; ++left)
    if (model.exact_step_is_due(due_at, left))
      least_steps_left = left;
  std::cout << "the run's end in view: exact at that staleness with " << least_steps_left
            << " steps left or more, iterating with fewer" << std::endl;
  double exact_now = 1.0, iterate_on = 0;
  for (unsigned int k = 0; k < least_steps_left; ++k)
    {
      exact_now += k > 0 ? model.predicted_iterating_seconds(k) : 0.;
      iterate_on += model.predicted_iterating_seconds(due_at + k);
    }
  tests::check("  with the last step, never exact", !model.exact_step_is_due(due_at, 1));
  tests::check("  exact where it repays itself by the end, and only there",
               least_steps_left > 1 && exact_now < iterate_on && model.exact_step_is_due(due_at, 64));
  tests::check("  never exact where the rule alone says not", !model.exact_step_is_due(due_at - 1, 64));

  // The same cycle, but from staleness 2 on every step also refreshed a cut's columns, at
  // 0.5 s a step on top of its iterations.
  const auto cut_model = [](const bool seconds_counted) {
    fem::StepCostModel cut;
    cut.record_iterations(cholesky::Refresh::all, 1, 0.02);
    cut.record_exact_step(1.0, 0);
    cut.record_iterating_step(1, 0.1 + 0.02 * 2, 2);
    for (unsigned int s = 2; s <= 20; ++s)
      if (seconds_counted)
        cut.record_iterating_step(s, 0.5 + 0.1 + 0.02 * (s + 1), s + 1);
      else
        cut.record_iterations_at(s, s + 1);
    return first_due(cut);
  };
  const unsigned int cut_due = cut_model(false), cut_due_counted = cut_model(true);
  std::cout << "through an incision: exact due at staleness " << cut_due << " from the iterations, at "
            << cut_due_counted << " had the cut's seconds been counted" << std::endl;
  tests::check("  the iterations alone give the same rule", cut_due == due_at && cut_due_counted < due_at);
}
