// Stability under extreme motion, every model, the small torus (200 vertices, 960 tets):
// - a fast spin: no support, no load, no damping, an initial angular velocity of 0.32 and
//   3.2 rad per step;
// - a violent pull: the tool of small_torus_scene 20 times faster (10 m/s) on springs 100
//   times stiffer (2000 N/m), no gravity (torus_pull.prm's setting), 2 m; then the tool
//   lets go of the state after 100 steps: elements inverted on the way must come back
//   (Irving's handling);
// - release after a large stretch: the torus pulled 0.4 m by the corotational model, then
//   let go (no tool, no gravity) from there.
// A row per case and model (stability_tests.h): bounded (the energy the body holds never
// above 1.1 times what was put in), finite, factorizations, the largest energy ratio.

#include "stability_tests.h"

#include <warpchol/app/simulation.h>

#include <regex>
#include <sstream>

int main()
{
  const auto models = tests::stability_models();

  tests::TorusCase spin;
  spin.fixed_far_side = false;
  spin.gravity        = "0, 0, 0";
  spin.tool_stiffness = "0";
  spin.damping        = "0";
  for (const auto &[label, rate] : {std::pair<std::string, std::string>{"spin 0.32 rad/step", "10, 30, 0"},
                                    {"spin 3.2 rad/step", "100, 300, 0"}})
    {
      spin.angular_velocity = rate;
      for (const auto &[model_label, model] : models)
        tests::print_stability_row(label, model_label, tests::run_stability_case(spin.text(), model, 200));
    }

  // The violent pull as torus_pull.prm has it: no gravity. Then the tool lets go (from the
  // state after 100 steps, heavier damping) and every inverted element must come back.
  tests::TorusCase pull;
  pull.gravity        = "0, 0, 0";
  pull.tool_velocity  = "0, 10, 0";
  pull.tool_stiffness = "2000";
  tests::TorusCase let_go = pull;
  let_go.tool_stiffness   = "0";
  let_go.damping          = "1";
  for (const auto &[label, model] : models)
    {
      const auto run = tests::run_stability_case(pull.text(), model, 200);
      tests::print_stability_row("violent pull", label, run);
      std::cout << "  peak energy held " << warpchol::format_number(run.max_held_energy, 2)
                << " J; elements inverted on the way: " << (run.max_inverted > 0 ? "yes" : "none")
                << std::endl;
      warpchol::app::Scene held_scene{warpchol::app::AllParameters("stability_case.prm")};
      warpchol::fem::StepStatistics statistics;
      for (unsigned int step = 0; step < 100; ++step)
        held_scene.integrator().advance(statistics);
      const auto released = tests::run_stability_case(let_go.text(), model, 200,
                                                       held_scene.integrator().positions(),
                                                       held_scene.integrator().velocities());
      tests::print_stability_row("violent pull, let go", label, released);
      std::cout << "  every element upright at the end: " << (released.inverted_at_end == 0 ? "yes" : "NO")
                << std::endl;
    }

  tests::TorusCase stretch;
  stretch.tool_velocity  = "0, 2, 0";
  stretch.tool_stiffness = "200";
  stretch.gravity        = "0, 0, 0";
  const auto stretched =
    tests::run_scene("stretch.prm", stretch.text() + "subsection Model\n  set Type = corotational\nend\n", 20);
  tests::TorusCase release = stretch;
  release.tool_stiffness   = "0";
  for (const auto &[label, model] : models)
    tests::print_stability_row("release after stretch", label,
                               tests::run_stability_case(release.text(), model, 200, stretched));

  // The program stops the runaway spin of stiffness warping with one line (Time
  // stepping/Energy growth limit at its default, 10), its figures masked here.
  tests::write_file("runaway_spin.prm",
                    std::regex_replace(spin.text(), std::regex("  set Energy growth limit = 0\n"), "") +
                      "subsection Model\n  set Type = stiffness_warping\nend\n"
                      "subsection Time stepping\n  set Number of steps = 200\nend\n"
                      "subsection Output\n  set Directory = results\n  set Write log = true\nend\n");
  std::vector<const char *> argv{"warpchol", "runaway_spin.prm"};
  std::ostringstream        out, err;
  const int                 status = warpchol::app::main(argv.size(), argv.data(), out, err);
  std::cout << "runaway spin, stiffness_warping: exit " << status << ", "
            << std::regex_replace(err.str(), std::regex(R"([0-9][0-9.e+-]*)"), "#");
}
