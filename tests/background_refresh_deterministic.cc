// The refresh on the second core (Model/Strategy = background): with a fixed lag (the
// refresh of step k taken at step k + lag, the step waiting for it) the trajectory is the
// same to the bit on one thread and on two, and equals the synchronous exact one
// (corotational, refactored every step) to the CG tolerance; taken as soon as it is done
// (lag 0) it equals it to the tolerance as well. The steps must actually have taken
// refreshes, with the lag they were told.

#include "simulation_tests.h"

#include <cstring>

namespace
{
  /** The small torus, its tool faster (more rotation), the model and solver sections. */
  std::string scene(const std::string &model_section, const unsigned int threads)
  {
    std::string text = tests::small_torus_scene(model_section);
    text.replace(text.find("set Velocity = 0, 0.5, 0"), 24, "set Velocity = 0, 2.0, 0");
    return text + "subsection Solver\n  set Threads = " + std::to_string(threads) + "\nend\n";
  }

  std::string background(const unsigned int lag)
  {
    return "  set Type = warp_canceling\n  set Strategy = background\n  set CG tolerance = 1e-11\n"
           "  set Background lag = " + std::to_string(lag) + "\n";
  }

  struct Run
  {
    std::vector<warpchol::fem::Vector3> positions;
    unsigned int                        refreshes = 0;
    int                                 largest_lag = -1;
    unsigned int                        iterations = 0;
  };

  Run run(const std::string &name, const std::string &text, const unsigned int steps)
  {
    tests::write_file(name, text);
    warpchol::app::Scene scene{warpchol::app::AllParameters(name)};
    Run                  result;
    for (unsigned int step = 0; step < steps; ++step)
      {
        warpchol::fem::StepStatistics statistics;
        scene.integrator().advance(statistics);
        result.refreshes += statistics.refresh == "background";
        result.largest_lag = std::max(result.largest_lag, statistics.factor_lag);
        result.iterations += statistics.cg_iterations;
      }
    result.positions = scene.integrator().positions();
    return result;
  }

  bool same_bits(const std::vector<warpchol::fem::Vector3> &a, const std::vector<warpchol::fem::Vector3> &b)
  {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0;
  }
} // namespace

int main()
{
  const unsigned int steps = 30;
  const Run corotational = run("corotational.prm", scene("  set Type = corotational\n", 1), steps);
  const warpchol::app::Scene rest_scene{warpchol::app::AllParameters("corotational.prm")};
  const auto &rest = rest_scene.body().rest_positions();
  const Run stale = run("stale.prm",
                        scene("  set Type = warp_canceling\n  set Rerotation threshold = inf\n  set Strategy = "
                              "preconditioned\n  set CG tolerance = 1e-11\n", 1),
                        steps);

  for (const unsigned int lag : {1u, 3u})
    {
      std::cout << "lag " << lag << ":" << std::endl;
      const Run one = run("one.prm", scene(background(lag), 1), steps);
      const Run two = run("two.prm", scene(background(lag), 2), steps);
      tests::check("  one thread and two: the same bits", same_bits(one.positions, two.positions));
      tests::check_below("  against the synchronous exact run",
                         tests::relative_difference(one.positions, corotational.positions, rest), 1e-8);
      std::cout << "  refreshes taken " << one.refreshes << ", largest lag " << one.largest_lag << std::endl;
      tests::check("  fewer CG iterations than with the stale rest factor", one.iterations < stale.iterations);
    }
  const Run free_running = run("free.prm", scene(background(0), 2), steps);
  tests::check_below("lag 0 (taken when done), against the synchronous exact run",
                     tests::relative_difference(free_running.positions, corotational.positions, rest), 1e-8);
  tests::check("lag 0 took refreshes", free_running.refreshes > 0);
}
