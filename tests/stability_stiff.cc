// Stiff materials at a fixed time step (0.01 s), every model, on the pull of the small
// torus (200 vertices, 960 tets; gravity, a tool lifting the near side, far side held):
// Young's modulus from 50 Pa to 1e9 Pa, and Poisson's ratio up to 0.499 (nearly
// incompressible: lambda 250 times mu). A row per case and model (stability_tests.h).

#include "stability_tests.h"

int main()
{
  const auto models = tests::stability_models();
  const std::vector<std::pair<std::string, std::string>> materials = {
    {"50", "0.45"}, {"1e5", "0.45"}, {"1e9", "0.45"}, {"50", "0.49"}, {"50", "0.499"}};
  for (const auto &[youngs_modulus, poisson_ratio] : materials)
    {
      tests::TorusCase stiff;
      stiff.youngs_modulus = youngs_modulus;
      stiff.poisson_ratio  = poisson_ratio;
      for (const auto &[label, model] : models)
        tests::print_stability_row("E " + youngs_modulus + ", nu " + poisson_ratio, label,
                                   tests::run_stability_case(stiff.text(), model, 200));
    }
}
