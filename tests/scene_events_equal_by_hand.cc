// A scene may hold any number of cuts, grasps and material changes (numbered subsections
// "Cut 2", "Grasp 2", ...), each with its own times, a blade and jaws on recorded paths.
// Two cuts, two grasps and a material change read from a parameter file give the run that
// the same events give when applied by hand through fem::Surgery (ImplicitEuler::set_surgery)
// to the scene without them: the same positions and velocities to 1e-12.

#include "simulation_tests.h"

#include <warpchol/surgery/instrument_path.h>
#include <warpchol/surgery/surgery.h>

#include <iomanip>
#include <limits>
#include <sstream>

using namespace warpchol;

namespace
{
  std::string scene(const std::string &events)
  {
    return tests::without_subsection(
             tests::small_torus_scene("  set Type = warp_canceling\n  set Rerotation threshold = 0.3\n"), "Tool") +
           "subsection Solver\n  set Ordering = metis\n  set Change method = flops\nend\n"
           "subsection Time stepping\n  set Number of steps = 25\nend\n" + events;
  }

  // The blade of Cut 2 and the jaws of Grasp 2, as a device would record them.
  const std::vector<double> blade_times{0.02, 0.04, 0.05, 0.06, 0.08};
  const std::vector<double> blade_values{-0.15, -0.2, 0.30, -0.15, 0.2, 0.30,  //
                                         -0.05, -0.2, 0.31, -0.05, 0.2, 0.32,  //
                                         0.00,  -0.2, 0.33, 0.00,  0.2, 0.33,  //
                                         0.05,  -0.2, 0.31, 0.05,  0.2, 0.30,  //
                                         0.15,  -0.2, 0.30, 0.15,  0.2, 0.30};
  const std::vector<double> jaws_times{0.07, 0.1, 0.13, 0.3};
  const std::vector<double> jaws_values{0.23, 0, 0.21, 0.23, 0.02, 0.21, 0.22, 0.05, 0.2, 0.22, 0.06, 0.2};

  std::string csv(const std::vector<double> &times, const std::vector<double> &values)
  {
    const std::size_t  n = values.size() / times.size();
    std::ostringstream out;
    out << std::setprecision(17) << "time,values\n";
    for (std::size_t k = 0; k < times.size(); ++k)
      {
        out << times[k];
        for (std::size_t j = 0; j < n; ++j)
          out << ", " << values[k * n + j];
        out << "\n";
      }
    return out.str();
  }

  const std::string events = "subsection Cut\n"
                             "  set Blade start = 0.31, -0.2, -0.15\n"
                             "  set Blade end   = 0.31, 0.2, -0.15\n"
                             "  set Velocity    = 0, 0, 10\n"
                             "  set Start time  = 0.02\n"
                             "  set Duration    = 0.03\n"
                             "end\n"
                             "subsection Cut 2\n"
                             "  set Path file  = blade.csv\n"
                             "  set Start time = 0.03\n"
                             "  set Duration   = 0.04\n"
                             "end\n"
                             "subsection Grasp\n"
                             "  set Sphere center = -0.05, 0, -0.3\n"
                             "  set Sphere radius = 0.06\n"
                             "  set Velocity      = 0, 0.5, 0\n"
                             "  set Duration      = 0.05\n"
                             "  set Grasp time    = 0.05\n"
                             "  set Release time  = 0.12\n"
                             "end\n"
                             "subsection Grasp 2\n"
                             "  set Path file     = jaws.csv\n"
                             "  set Sphere radius = 0.06\n"
                             "  set Grasp time    = 0.08\n"
                             "end\n"
                             "subsection Material change\n"
                             "  set Region           = sphere\n"
                             "  set Sphere center    = -0.3, 0, 0\n"
                             "  set Sphere radius    = 0.12\n"
                             "  set Time             = 0.04\n"
                             "  set Stiffness factor = 5\n"
                             "end\n";
} // namespace

int main()
{
  tests::write_file("blade.csv", csv(blade_times, blade_values));
  tests::write_file("jaws.csv", csv(jaws_times, jaws_values));
  tests::write_file("events.prm", scene(events));
  tests::write_file("plain.prm", scene(""));
  app::Scene from_file{app::AllParameters("events.prm")};
  app::Scene by_hand{app::AllParameters("plain.prm")};
  std::cout << "events read: " << from_file.parameters().cuts.size() << " cuts, " << from_file.parameters().grasps.size()
            << " grasps, " << from_file.parameters().material_changes.size() << " material change" << std::endl;

  // The same events, built by hand.
  const fem::ElasticBody   &body = by_hand.body();
  std::vector<fem::Blade>   blades{fem::Blade{{0.31, -0.2, -0.15}, {0.31, 0.2, -0.15}, {0, 0, 10}, 0.02, 0.03},
                                   fem::Blade{{}, {}, {}, 0.03, 0.04, fem::InstrumentPath(blade_times, blade_values, 6)}};
  std::vector<fem::Grasp>   grasps{fem::Grasp{{-0.05, 0, -0.3}, 0.06, {0, 0.5, 0}, 0.05, 0.05, 0.12, 0},
                                   fem::Grasp{{}, 0.06, {}, 0, 0.08, std::numeric_limits<double>::infinity(), 0,
                                              fem::InstrumentPath(jaws_times, jaws_values, 3)}};
  fem::MaterialChange       change{{}, 0.04, 5};
  for (unsigned int e = 0; e < body.n_elements(); ++e)
    {
      bool inside = true;
      for (const unsigned int v : body.element_vertices(e))
        inside = inside && (body.rest_positions()[v] - fem::Vector3(-0.3, 0, 0)).norm() <= 0.12;
      if (inside)
        change.elements.push_back(e);
    }
  by_hand.integrator().set_surgery(fem::Surgery(blades, grasps, {change}));

  fem::StepStatistics totals;
  for (unsigned int step = 0; step < 25; ++step)
    {
      fem::StepStatistics file_step, hand_step;
      from_file.integrator().advance(file_step);
      by_hand.integrator().advance(hand_step);
      totals.elements_cut += file_step.elements_cut;
      totals.vertices_grasped += file_step.vertices_grasped;
      totals.vertices_released += file_step.vertices_released;
      totals.elements_changed += file_step.elements_changed;
      if (file_step.elements_cut != hand_step.elements_cut || file_step.vertices_grasped != hand_step.vertices_grasped ||
          file_step.vertices_released != hand_step.vertices_released ||
          file_step.elements_changed != hand_step.elements_changed)
        std::cout << "step " << step << ": the events differ" << std::endl;
    }
  std::cout << "elements cut " << totals.elements_cut << ", vertices grasped " << totals.vertices_grasped
            << ", released " << totals.vertices_released << ", elements changed " << totals.elements_changed
            << std::endl;
  tests::check("both cuts cut, both grasps held, the material changed",
               totals.elements_cut > 0 && totals.vertices_grasped > 0 && totals.vertices_released > 0 &&
                 totals.elements_changed > 0);
  const auto &rest = body.rest_positions();
  tests::check_below("positions from the file against by hand",
                     tests::relative_difference(from_file.integrator().positions(), by_hand.integrator().positions(),
                                                rest),
                     1e-12);
  tests::check_below("velocities",
                     tests::relative_difference(from_file.integrator().velocities(), by_hand.integrator().velocities(),
                                                std::vector<fem::Vector3>(rest.size(), fem::Vector3::Zero())),
                     1e-12);
}
