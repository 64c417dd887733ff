// Every backend (Solver/Backend) reproduces the exact corotational trajectory of the small
// torus scene solved by warpchol's factor: the direct peers to rounding, the iterative ones
// to their tolerance. A direct peer under warp-canceling corotation gives warpchol's WCC
// trajectory (it refactorizes in full what warpchol refactorizes in part). A bad backend
// name is refused with the list of the valid ones, and so are the combinations a peer
// cannot run.

#include "simulation_tests.h"

#include <warpchol/backends/linear_solver.h>

namespace
{
  /** The small torus scene, its tool faster (more rotation), solved by @p backend. */
  std::string scene(const std::string &model_section, const std::string &backend,
                    const std::string &tolerance = "1e-10")
  {
    std::string text = tests::small_torus_scene(model_section);
    text.replace(text.find("set Velocity = 0, 0.5, 0"), 24, "set Velocity = 0, 2.0, 0");
    return text + "subsection Solver\n  set Backend = " + backend + "\n  set Tolerance = " + tolerance + "\nend\n";
  }

  const std::string corotational = "  set Type = corotational\n";
  const std::string wcc          = "  set Type = warp_canceling\n  set Rerotation threshold = 0.3\n";
} // namespace

int main()
{
  // No MPI_InitFinalize: the Trilinos backend starts MPI itself, as in the programs.
  using warpchol::backends::Backend;
  const unsigned int steps = 30;

  const auto exact = tests::run_scene("warpchol.prm", scene(corotational, "warpchol"), steps);
  const warpchol::app::Scene rest_scene{warpchol::app::AllParameters("warpchol.prm")};
  const auto &rest = rest_scene.body().rest_positions();
  const auto  warped = tests::run_scene("warped.prm", scene(wcc, "warpchol"), steps);
  tests::check("WCC at threshold 0.3 differs from corotational by more than 1e-4",
               tests::relative_difference(warped, exact, rest) > 1e-4);

  for (const Backend backend : warpchol::backends::all_backends())
    {
      const std::string name = warpchol::backends::to_string(backend);
      if (backend == Backend::warpchol)
        continue;
      const auto x = tests::run_scene(name + ".prm", scene(corotational, name), steps);
      const double bound = warpchol::backends::iterates(backend) ? 1e-7 : 1e-10;
      tests::check_below(name + ": corotational vs warpchol's", tests::relative_difference(x, exact, rest), bound);
      if (warpchol::backends::iterates(backend))
        {
          // A loose tolerance: still within it, and farther than the tight one.
          const auto loose = tests::run_scene(name + "_loose.prm", scene(corotational, name, "1e-4"), steps);
          const double difference = tests::relative_difference(loose, exact, rest);
          tests::check_below(name + " to 1e-4: corotational vs warpchol's", difference, 1e-2);
          tests::check(name + " to 1e-4 differs from warpchol's by more than the tight tolerance",
                       difference > tests::relative_difference(x, exact, rest));
        }
      else
        {
          const auto y = tests::run_scene(name + "_wcc.prm", scene(wcc, name), steps);
          tests::check_below(name + ": WCC vs warpchol's WCC", tests::relative_difference(y, warped, rest), 1e-10);
        }
    }

  tests::expect_error("a bad backend name", [] {
    tests::write_file("bad.prm", scene(corotational, "pardiso"));
    warpchol::app::AllParameters parameters("bad.prm");
  });
  tests::expect_error("cholmod with WCC's preconditioned strategy", [] {
    tests::write_file("strategy.prm", scene(wcc + "  set Strategy = preconditioned\n", "cholmod"));
    warpchol::app::AllParameters parameters("strategy.prm");
  });
  tests::expect_error("umfpack with a target error", [] {
    tests::write_file("target.prm", scene(wcc + "  set Target error = 0.01\n", "umfpack"));
    warpchol::app::AllParameters parameters("target.prm");
  });
  tests::expect_error("warp_preconditioned_cg with WCC", [] {
    tests::write_file("warp.prm", scene(wcc, "warp_preconditioned_cg"));
    warpchol::app::AllParameters parameters("warp.prm");
  });
  tests::expect_error("a tolerance of 1", [] {
    tests::write_file("tolerance.prm", scene(corotational, "trilinos_amg_cg", "1"));
    warpchol::app::AllParameters parameters("tolerance.prm");
  });
}
