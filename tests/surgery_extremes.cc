// The extremes of cuts, grasps and material changes, each a documented behaviour or a
// one-line error: a cut that detaches a piece (it falls freely: A stays positive definite
// through its mass), a cut that removes every element (every vertex a free particle), a
// blade that misses the mesh (nothing is cut, the summary says so), jaws that close on no
// vertex or on fixed ones only, a stiffness factor <= 0, changes whose time falls after the
// run's end (one warning line).

#include "simulation_tests.h"

#include <warpchol/app/simulation.h>

#include <sstream>

namespace
{
  /** A box 0.4 x 0.1 x 0.1 held at x = 0, gravity along -z, the model and @p extra. */
  std::string box(const std::string &extra)
  {
    return "subsection Mesh\n  set Source = box\n  set Box upper corner = 0.4, 0.1, 0.1\n"
           "  set Box subdivisions = 8, 2, 2\nend\n"
           "subsection Material\n  set Young's modulus = 1000\n  set Density = 100\nend\n"
           "subsection Time stepping\n  set Time step = 0.01\n  set Number of steps = 30\nend\n"
           "subsection Model\n  set Type = warp_canceling\n  set Rerotation threshold = 0.3\nend\n"
           "subsection Fixed vertices\n  set Region = box\n  set Box lower corner = -1, -1, -1\n"
           "  set Box upper corner = 1e-6, 1, 1\nend\n"
           "subsection Gravity\n  set Acceleration = 0, 0, -9.81\nend\n"
           "subsection Output\n  set Print timings = false\n  set Progress = off\nend\n" + extra;
  }

  /** A blade whose edge spans the box along y at x = @p x, rising along z through it. */
  std::string blade(const double x, const double half_width = 0.2)
  {
    return "subsection Cut\n  set Blade start = " + std::to_string(x) + ", -" + std::to_string(half_width) +
           ", -0.05\n  set Blade end = " + std::to_string(x) + ", " + std::to_string(half_width) +
           ", -0.05\n  set Velocity = 0, 0, 10\n  set Start time = 0.05\n  set Duration = 0.03\nend\n";
  }

  /** Run @p text's scene through the Simulation; its summary's surgery line. */
  std::string run(const std::string &name, const std::string &text, warpchol::app::Simulation **kept = nullptr)
  {
    tests::write_file(name, text);
    static std::unique_ptr<warpchol::app::Simulation> simulation;
    simulation = std::make_unique<warpchol::app::Simulation>(warpchol::app::AllParameters(name));
    std::ostringstream summary;
    simulation->run(summary);
    if (kept)
      *kept = simulation.get();
    // The counts of the summary's surgery line (its costs depend on the machine's ordering).
    const std::string text_out = summary.str();
    const auto        begin    = text_out.find("surgery:");
    if (begin == std::string::npos)
      return "no surgery line";
    const std::string line = text_out.substr(begin, text_out.find('\n', begin) - begin);
    return line.substr(0, line.find(';'));
  }
} // namespace

int main()
{
  // Detached: the end beyond x = 0.3 falls freely, every vertex of it at g t.
  warpchol::app::Simulation *simulation = nullptr;
  std::cout << "detach: " << run("detach.prm", box(blade(0.31)), &simulation) << std::endl;
  {
    const auto &scene = simulation->scene(0);
    const auto &rest  = scene.body().rest_positions();
    const auto &v     = scene.integrator().velocities();
    double      spread = 0, mean = 0;
    unsigned    n      = 0;
    for (unsigned int i = 0; i < rest.size(); ++i)
      if (rest[i][0] > 0.32)
        {
          mean += v[i][2];
          ++n;
        }
    mean /= n;
    for (unsigned int i = 0; i < rest.size(); ++i)
      if (rest[i][0] > 0.32)
        spread = std::max(spread, (v[i] - warpchol::fem::Vector3(0, 0, mean)).norm());
    tests::check("  the piece moves as one body (its velocities within 5 % of their mean)", spread <= 0.05 * std::abs(mean));
    tests::check("  falling", mean < -0.5);
  }

  // Every element: a cube split into the 6 tetrahedra around its diagonal (Kuhn's split),
  // the blade sweeping the plane across the diagonal's middle, which crosses all six. Every
  // vertex is then a free particle: those not fixed fall freely (dv = g dt each step).
  {
    tests::write_file("everything.prm",
                      "subsection Mesh\n  set Source = box\n  set Box upper corner = 0.1, 0.1, 0.1\n"
                      "  set Box subdivisions = 1, 1, 1\n  set Box sliver flattening = 0.999\nend\n"
                      "subsection Material\n  set Young's modulus = 1000\n  set Density = 100\nend\n"
                      "subsection Fixed vertices\n  set Region = box\n  set Box lower corner = -1, -1, -1\n"
                      "  set Box upper corner = 1e-6, 1, 1\nend\n"
                      "subsection Gravity\n  set Acceleration = 0, 0, -9.81\nend\n"
                      // The plane x + y + z = 0.15: the edge along (1, -1, 0), swept along (1, 1, -2).
                      "subsection Cut\n  set Blade start = -0.15, 0.15, 0.15\n  set Blade end = 0.15, -0.15, 0.15\n"
                      "  set Velocity = 1, 1, -2\n  set Start time = 0\n  set Duration = 0.2\nend\n");
    warpchol::app::Scene scene{warpchol::app::AllParameters("everything.prm")};
    unsigned int         cut = 0;
    for (unsigned int step = 0; step < 25; ++step)
      {
        warpchol::fem::StepStatistics statistics;
        scene.integrator().advance(statistics);
        cut += statistics.elements_cut;
      }
    const auto before = scene.integrator().velocities();
    warpchol::fem::StepStatistics statistics;
    scene.integrator().advance(statistics);
    bool falling_freely = true;
    for (unsigned int i = 0; i < scene.body().n_vertices(); ++i)
      if (!scene.body().is_fixed(i))
        falling_freely = falling_freely && scene.body().free_particle_mass(i) > 0 &&
                         (scene.integrator().velocities()[i] - before[i] - warpchol::fem::Vector3(0, 0, -0.0981)).norm() < 1e-12;
    std::cout << "everything: " << cut << " of " << scene.body().n_elements() << " elements cut" << std::endl;
    tests::check("  every free vertex is a free particle falling freely", falling_freely);
  }

  std::cout << "missing the mesh: " << run("missing.prm", box(blade(2.0))) << std::endl;

  // A change whose time falls after the run's end (30 steps: 0.3 s) would silently be
  // nothing: the summary warns in one line (issue 29).
  {
    tests::write_file("after_end.prm",
                      box("subsection Material change\n  set Region = sphere\n  set Sphere center = 0.2, 0.05, 0.05\n"
                          "  set Sphere radius = 0.05\n  set Time = 0.5\n  set Stiffness factor = 10\nend\n"
                          "subsection Grasp\n  set Sphere center = 0.4, 0.05, 0.05\n  set Sphere radius = 0.02\n"
                          "  set Grasp time = 0.6\nend\n"));
    warpchol::app::Simulation simulation{warpchol::app::AllParameters("after_end.prm")};
    std::ostringstream        summary;
    simulation.run(summary);
    const std::string text  = summary.str();
    const auto        begin = text.find("warning:");
    std::cout << "after the end: "
              << (begin == std::string::npos ? "no warning" : text.substr(begin, text.find('\n', begin) - begin))
              << std::endl;
    tests::check("  one warning line", begin != std::string::npos && text.find("warning:", begin + 1) == std::string::npos);
  }

  // Errors, through the program: one line, exit 2.
  const std::string jaws = "subsection Grasp\n  set Sphere radius = 0.02\n  set Grasp time = 0.05\n";
  tests::write_file("no_vertex.prm", box(jaws + "  set Sphere center = 1, 1, 1\nend\n"));
  std::cout << "grasp of no vertex: " << tests::run_warpchol({"no_vertex.prm"}) << std::endl;
  tests::write_file("fixed.prm", box(jaws + "  set Sphere center = 0, 0.05, 0.05\nend\n"));
  std::cout << "grasp of fixed vertices: " << tests::run_warpchol({"fixed.prm"}) << std::endl;
  tests::write_file("nonpositive.prm",
                    box("subsection Material change\n  set Region = sphere\n  set Sphere center = 0.2, 0.05, 0.05\n"
                        "  set Sphere radius = 0.05\n  set Stiffness factor = -2\nend\n"));
  std::cout << "E <= 0: " << tests::run_warpchol({"nonpositive.prm"}) << std::endl;
  tests::write_file("zero.prm",
                    box("subsection Material change\n  set Region = sphere\n  set Sphere center = 0.2, 0.05, 0.05\n"
                        "  set Sphere radius = 0.05\n  set Stiffness factor = 0\nend\n"));
  std::cout << "E = 0: " << tests::run_warpchol({"zero.prm"}) << std::endl;
}
