// A material change scales the stiffness of a region's elements at a step: their columns
// are re-assembled and refactorized partially. The run then goes on as a run that starts
// from the same state with that material from its first step, factored in full (the
// up-looking method refactors everything), to 1e-10; and differs from a run without the
// change by far more. With the linear model and with stiffness warping (WCC at inf).

#include "simulation_tests.h"

namespace
{
  std::string scene(const std::string &model_section, const double change_time, const std::string &method)
  {
    return tests::without_subsection(tests::small_torus_scene(model_section), "Tool") +
           "subsection Material change\n"
           "  set Region           = sphere\n"
           "  set Sphere center    = 0.3, 0, 0\n"
           "  set Sphere radius    = 0.12\n"
           "  set Time             = " + std::to_string(change_time) + "\n"
           "  set Stiffness factor = 20\n"
           "end\n"
           "subsection Solver\n  set Method = " + method + "\nend\n";
  }

  unsigned int advance(warpchol::app::Scene &scene, const unsigned int steps)
  {
    unsigned int changed = 0;
    for (unsigned int step = 0; step < steps; ++step)
      {
        warpchol::fem::StepStatistics statistics;
        scene.integrator().advance(statistics);
        changed += statistics.elements_changed;
      }
    return changed;
  }
} // namespace

int main()
{
  for (const std::string model : {"  set Type = linear\n",
                                  "  set Type = warp_canceling\n  set Rerotation threshold = inf\n"})
    {
      std::cout << model.substr(model.find('=') + 2, model.find('\n') - model.find('=') - 2) << ":" << std::endl;
      // Changed at 0.1 s, the start of step 11.
      tests::write_file("changed.prm", scene(model, 0.1, "supernodal"));
      warpchol::app::Scene changed{warpchol::app::AllParameters("changed.prm")};
      tests::write_file("unchanged.prm", scene(model, 1e9, "supernodal"));
      warpchol::app::Scene unchanged{warpchol::app::AllParameters("unchanged.prm")};
      advance(changed, 10);
      advance(unchanged, 10);

      tests::write_file("from_then.prm", scene(model, 0, "up"));
      warpchol::app::Scene from_then{warpchol::app::AllParameters("from_then.prm")};
      from_then.integrator().set_initial_positions(changed.integrator().positions());
      from_then.integrator().set_initial_velocities(changed.integrator().velocities());

      const unsigned int n_changed = advance(changed, 20);
      advance(unchanged, 20);
      advance(from_then, 20);
      const auto &rest = changed.body().rest_positions();
      std::cout << "  elements changed: " << n_changed << std::endl;
      tests::check("  some elements changed", n_changed > 10);
      tests::check_below("  against a run with the new material from then on, factored in full",
                         tests::relative_difference(changed.integrator().positions(), from_then.integrator().positions(), rest),
                         1e-10);
      tests::check("  a run without the change differs by more than 1e-3",
                   tests::relative_difference(unchanged.integrator().positions(), changed.integrator().positions(), rest) >
                     1e-3);
    }
}
