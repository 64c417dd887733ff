// A peer backend (Solver/Backend) factors and solves the steps; warpchol's solver beside it
// only analyzes A (the flops of a full factorization, which the statistics count) and holds
// no numeric factor (it held one as large as the peer's: 262 MiB at 60k unknowns). A WCC
// step where nothing changed factors nothing with a peer either. warpchol's own factor is
// there when warpchol solves.

#include "simulation_tests.h"

namespace
{
  /** Five steps of the small torus, @p model_section, solved by @p backend. */
  void run(const std::string &label, const std::string &model_section, const std::string &backend)
  {
    const std::string file = label + ".prm";
    tests::write_file(file, tests::small_torus_scene(model_section) + "subsection Solver\n  set Backend = " +
                              backend + "\nend\n");
    warpchol::app::Scene scene{warpchol::app::AllParameters(file)};
    unsigned int         refactorized = 0;
    double               flops_full   = 0;
    for (unsigned int step = 0; step < 5; ++step)
      {
        warpchol::fem::StepStatistics statistics;
        scene.integrator().advance(statistics);
        refactorized += statistics.refactorized;
        flops_full = statistics.flops_full;
      }
    const auto &solver = scene.model().solver();
    std::cout << label << ": warpchol's numeric factor "
              << (solver.numeric_bytes() == 0 ? "not held" :
                  solver.numeric_bytes() >= solver.statistics().nnz_l * sizeof(double) ? "held" : "PART OF IT")
              << ", analysis " << (solver.statistics().nnz_l > 0 ? "done" : "NOT DONE")
              << ", flops of a full factorization in the steps' statistics "
              << (flops_full == solver.statistics().flops && flops_full > 0 ? "yes" : "NO")
              << ", factorizations in 5 steps " << refactorized << std::endl;
  }
} // namespace

int main()
{
  const std::string corotational = "  set Type = corotational\n";
  run("corotational_cholmod", corotational, "cholmod");
  run("corotational_umfpack", corotational, "umfpack");
  run("corotational_warpchol", corotational, "warpchol");
  // Threshold inf updates no element: A never changes after the set-up.
  const std::string wcc_inf = "  set Type = warp_canceling\n  set Rerotation threshold = inf\n";
  run("wcc_inf_cholmod", wcc_inf, "cholmod");
  run("wcc_inf_warpchol", wcc_inf, "warpchol");
}
