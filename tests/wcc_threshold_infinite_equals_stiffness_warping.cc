// Warp-canceling corotation with an infinite threshold never updates an element: A stays
// the rest matrix and only the nodal rotations follow the body, which is stiffness warping
// with exact corotated forces. Both runs must agree to rounding after 20 steps, and WCC must
// never have refactorized.

#include "simulation_tests.h"

int main()
{
  const auto warping = tests::run_scene(
    "warping.prm", tests::small_torus_scene("  set Type = stiffness_warping\n"), 20);

  tests::write_file("wcc.prm", tests::small_torus_scene(
                                 "  set Type = warp_canceling\n  set Rerotation threshold = inf\n"));
  warpchol::app::Scene wcc{warpchol::app::AllParameters("wcc.prm")};
  bool never_rerotated = true;
  for (unsigned int step = 0; step < 20; ++step)
    {
      warpchol::fem::StepStatistics statistics;
      wcc.integrator().advance(statistics);
      never_rerotated = never_rerotated && statistics.elements_rerotated == 0 && !statistics.refactorized;
    }
  const auto &rest = wcc.body().rest_positions();
  tests::check_below("WCC(inf) vs stiffness warping, relative",
                     tests::relative_difference(wcc.integrator().positions(), warping, rest), 1e-12);
  tests::check("WCC(inf) re-rotated no element and never refactorized", never_rerotated);
  tests::check("the factor was computed once",
               wcc.model().solver().statistics().n_factorizations == 1 &&
                 wcc.model().solver().statistics().n_refactorizations == 0);

  // And stiffness warping is not the exact corotational run: the comparison means something.
  const auto corotational = tests::run_scene(
    "corotational.prm", tests::small_torus_scene("  set Type = corotational\n"), 20);
  tests::check("stiffness warping differs from corotation by more than 1e-6",
               tests::relative_difference(warping, corotational, rest) > 1e-6);
}
