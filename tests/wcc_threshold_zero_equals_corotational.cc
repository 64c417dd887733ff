// Warp-canceling corotation with threshold 0 updates every element in every step: it must
// reproduce the exact corotational run (R A R^T with S = R, Q = R_e is R_e K_e R_e^T
// assembled), to rounding, after 20 steps of a scene that rotates and deforms the body;
// with the lumped and with the consistent mass matrix (whose off-diagonal blocks WCC must
// store rotated for this to hold).

#include "simulation_tests.h"

int main()
{
  for (const std::string mass : {"lumped", "consistent"})
    {
      const auto corotational = tests::run_scene(
        "corotational.prm", tests::small_torus_scene("  set Type = corotational\n", mass), 20);
      const auto wcc = tests::run_scene(
        "wcc.prm",
        tests::small_torus_scene("  set Type = warp_canceling\n  set Rerotation threshold = 0\n", mass),
        20);
      const auto linear = tests::run_scene(
        "linear.prm", tests::small_torus_scene("  set Type = linear\n", mass), 20);

      const warpchol::app::Scene rest_scene{warpchol::app::AllParameters("linear.prm")};
      const auto &rest = rest_scene.body().rest_positions();
      std::cout << mass << " mass:" << std::endl;
      tests::check_below("  WCC(0) vs corotational, relative", tests::relative_difference(wcc, corotational, rest), 1e-10);
      // The scene is not a small-displacement one: the linear model must differ visibly,
      // or the comparison above would prove nothing.
      tests::check("  linear differs from corotational by more than 1 %",
                   tests::relative_difference(linear, corotational, rest) > 0.01);
    }
}
