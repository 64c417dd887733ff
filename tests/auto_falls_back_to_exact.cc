// auto never loses to exact steps: on a scene built so that no fast strategy pays (every
// element's error over the update threshold, so every step updates all of them, and CG to
// 1e-10: no step of auto's own is cheaper than an exact one, each pays the error estimate
// and the iterations on top) a window of its own steps costs more than its exact steps,
// and it falls back to exact steps (the exact path's: every element updated, a direct
// solve), its trajectory that of the exact path to within CG's tolerance. Where its own
// steps pay clearly (the fine torus, 14625 tets, at threshold inf: no element updated, CG
// on the corotational matrix, about a fifth of an exact step) it does not fall back.
// Decisions on measured seconds: the scenes are built so that the margins are wide.

#include "simulation_tests.h"
#include "tests.h"

#include <warpchol/app/parameters.h>
#include <warpchol/app/scene.h>
#include <warpchol/fem/warp_canceling_model.h>

using namespace warpchol;

namespace
{
  struct Run
  {
    std::vector<fem::Vector3> positions;
    unsigned int              exact_steps = 0, fallbacks = 0;
  };

  Run run(const std::string &name, const std::string &scene_text, const unsigned int steps)
  {
    tests::write_file(name, scene_text);
    app::Scene scene{app::AllParameters(name)};
    for (unsigned int step = 0; step < steps; ++step)
      {
        fem::StepStatistics statistics;
        scene.integrator().advance(statistics);
      }
    Run result;
    result.positions = scene.integrator().positions();
    if (const auto *wcc = dynamic_cast<const fem::WarpCancelingModel *>(&scene.model()))
      {
        result.exact_steps = wcc->exact_fallback().exact_steps();
        result.fallbacks   = wcc->exact_fallback().fallbacks();
      }
    return result;
  }
} // namespace

int main()
{
  const unsigned int steps = 60;
  const Run          exact  = run("exact.prm",
                        tests::small_torus_scene("  set Type = warp_canceling\n"
                                                 "  set Update threshold = 0\n"),
                        steps);
  const Run          losing = run("losing.prm",
                         tests::small_torus_scene("  set Type = warp_canceling\n"
                                                  "  set Strategy = auto\n"
                                                  "  set Update threshold = 1e-12\n"
                                                  "  set CG tolerance = 1e-10\n"),
                         steps);
  tests::check("where nothing pays, auto falls back to exact steps", losing.fallbacks >= 1 && losing.exact_steps >= 1);
  const Run at_rest = run("rest.prm", tests::small_torus_scene("  set Type = warp_canceling\n"), 0);
  tests::check_below("its trajectory against the exact path's (relative to the motion)",
                     tests::relative_difference(losing.positions, exact.positions, at_rest.positions), 1e-3);

  const Run paying = run("paying.prm",
                         "subsection Mesh\n"
                         "  set Source = file\n"
                         "  set File   = " SOURCE_DIR "/../meshes/torus_fine.msh\n"
                         "end\n"
                         "subsection Time stepping\n"
                         "  set Time step          = 0.01\n"
                         "  set Rayleigh mass      = 0.1\n"
                         "  set Rayleigh stiffness = 0.1\n"
                         "end\n"
                         "subsection Model\n"
                         "  set Type             = warp_canceling\n"
                         "  set Strategy         = auto\n"
                         "  set Update threshold = inf\n"
                         "end\n"
                         "subsection Fixed vertices\n"
                         "  set Region           = box\n"
                         "  set Box lower corner = -1, -1, -1\n"
                         "  set Box upper corner = -0.33, 1, 1\n"
                         "end\n"
                         "subsection Gravity\n"
                         "  set Acceleration = 0, -9.81, 0\n"
                         "end\n",
                         30);
  tests::check("where its own steps pay, it does not fall back", paying.exact_steps == 0);
}
