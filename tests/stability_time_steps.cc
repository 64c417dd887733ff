// Large and tiny time steps, every model, on the pull of the small torus (200 vertices,
// 960 tets; gravity, a tool lifting the near side, far side held): dt 1e-5, 1e-3 and 0.1 s,
// 200 steps each (0.01 s is stability_stiff's E 50 Pa case). A row per case and model (stability_tests.h).

#include "stability_tests.h"

int main()
{
  const auto models = tests::stability_models();
  for (const std::string time_step : {"1e-5", "1e-3", "0.1"})
    {
      tests::TorusCase steps;
      steps.time_step = time_step;
      for (const auto &[label, model] : models)
        tests::print_stability_row("dt " + time_step, label,
                                   tests::run_stability_case(steps.text(), model, 200));
    }
}
