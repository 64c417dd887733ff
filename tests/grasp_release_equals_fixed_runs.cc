// A grasp ties the free vertices within the jaws to them by penalty springs (their
// diagonals change: their columns are refactorized, nothing else), a release unties them.
// Jaws that close at rest and do not move hold the vertices where they are: until the
// release the run equals the run with those vertices fixed, to the penalty's accuracy
// (1e-6 of the motion); after the release it equals a run started from the same state
// without them, to 1e-9 (the released run's factor is the grasped one updated, the other's
// a fresh factorization: their roundings differ, 2.3e-10 after 15 steps with the kernels'
// baseline target built by clang, under 1e-10 with GCC's AVX-512 build). With the linear
// model and with exact corotation.

#include "simulation_tests.h"

#include <sstream>

namespace
{
  /** The small torus, no tool, gravity, the model, and @p extra sections. */
  std::string scene(const std::string &model_section, const std::string &extra)
  {
    return tests::without_subsection(tests::small_torus_scene(model_section), "Tool") + extra;
  }

  const std::string jaws = "subsection Grasp\n"
                           "  set Sphere center = 0.4, 0, 0\n"
                           "  set Sphere radius = 0.1\n"
                           "  set Grasp time    = 0\n"
                           "  set Release time  = 0.1\n"
                           "end\n";

  void advance(warpchol::app::Scene &scene, const unsigned int steps, unsigned int *grasped = nullptr)
  {
    for (unsigned int step = 0; step < steps; ++step)
      {
        warpchol::fem::StepStatistics statistics;
        scene.integrator().advance(statistics);
        if (grasped)
          *grasped += statistics.vertices_grasped;
      }
  }
} // namespace

int main()
{
  for (const std::string model : {"  set Type = linear\n", "  set Type = corotational\n"})
    {
      std::cout << model.substr(model.find('=') + 2, model.find('\n') - model.find('=') - 2) << ":" << std::endl;
      tests::write_file("grasp.prm", scene(model, jaws));
      warpchol::app::Scene grasp{warpchol::app::AllParameters("grasp.prm")};
      unsigned int         grasped = 0;
      advance(grasp, 10, &grasped);

      // The grasped vertices: those within the jaws at rest (the torus's scene holds none
      // of them fixed).
      const auto                &rest = grasp.body().rest_positions();
      std::ostringstream         ids;
      unsigned int               n_within = 0;
      for (unsigned int v = 0; v < rest.size(); ++v)
        if ((rest[v] - warpchol::fem::Vector3(0.4, 0, 0)).norm() <= 0.1)
          ids << (n_within++ > 0 ? ", " : "") << v;
      std::cout << "  vertices grasped: " << grasped << std::endl;
      tests::check("  the jaws held the vertices within them", grasped == n_within && grasped > 0);

      // Held: the same as those vertices fixed (along with the scene's own).
      std::string fixed_text = scene(model, "");
      fixed_text             = tests::without_subsection(fixed_text, "Fixed vertices");
      std::ostringstream all_fixed;
      for (unsigned int v = 0; v < rest.size(); ++v)
        if (grasp.body().is_fixed(v) || (rest[v] - warpchol::fem::Vector3(0.4, 0, 0)).norm() <= 0.1)
          all_fixed << (all_fixed.tellp() > 0 ? ", " : "") << v;
      tests::write_file("fixed.prm", fixed_text + "subsection Fixed vertices\n  set Region = ids\n  set Vertex ids = " +
                                        all_fixed.str() + "\nend\n");
      warpchol::app::Scene fixed{warpchol::app::AllParameters("fixed.prm")};
      advance(fixed, 10);
      tests::check_below("  held: against the run with them fixed",
                         tests::relative_difference(grasp.integrator().positions(), fixed.integrator().positions(), rest),
                         1e-6);

      // Released at 0.1 s: the same as a run from that state without the springs.
      tests::write_file("free.prm", scene(model, ""));
      warpchol::app::Scene free{warpchol::app::AllParameters("free.prm")};
      free.integrator().set_initial_positions(grasp.integrator().positions());
      free.integrator().set_initial_velocities(grasp.integrator().velocities());
      advance(grasp, 15);
      advance(free, 15);
      tests::check_below("  released: against a run from that state without them",
                         tests::relative_difference(grasp.integrator().positions(), free.integrator().positions(), rest),
                         1e-9);
    }
}
