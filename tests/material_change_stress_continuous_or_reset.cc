// A material change that stiffens a strained region 1e8 times mid-run (issue 29), on the
// small torus lifted by its tool, the change at 0.1 s (the start of step 11):
// - with either Material change/Stress, continuous or reset, every model runs to the end
//   with the energy growth limit at its default (10): the change's energy is counted;
// - before the change the trajectory is that of a run without it, to the bit;
// - continuous: at the change the elastic forces (the stress) are unchanged and the elastic
//   energy is continuous but for the change's own energy (the changed elements' elastic
//   energy, divided by 1e8: it goes out); the stiffened region then holds its shape;
// - reset: the elastic energy jumps by the change's energy, and the region springs back
//   to its rest shape.

#include "simulation_tests.h"

#include <warpchol/app/simulation.h>

#include <sstream>

namespace
{
  /** The small torus without output, a 1e8 stiffening at @p change_time; @p stress, 30 steps. */
  std::string scene(const std::string &model_section, const double change_time, const std::string &stress)
  {
    return tests::small_torus_scene(model_section) +
           "subsection Time stepping\n"
           "  set Number of steps = 30\n"
           "end\n"
           "subsection Material change\n"
           "  set Region           = sphere\n"
           "  set Sphere center    = 0.3, 0, 0\n"
           "  set Sphere radius    = 0.12\n"
           "  set Time             = " + std::to_string(change_time) + "\n"
           "  set Stiffness factor = 1e8\n"
           "  set Stress           = " + stress + "\n"
           "end\n"
           "subsection Output\n"
           "  set Print timings = false\n"
           "  set Progress = off\n"
           "end\n";
  }

  void advance(warpchol::app::Scene &scene, const unsigned int steps)
  {
    for (unsigned int step = 0; step < steps; ++step)
      {
        warpchol::fem::StepStatistics statistics;
        scene.integrator().advance(statistics);
      }
  }

  /** The elastic forces of @p scene's body at @p positions, with the element rotations if @p rotated. */
  std::vector<warpchol::fem::Vector3> elastic_forces(const warpchol::app::Scene &scene,
                                                     const std::vector<warpchol::fem::Vector3> &positions,
                                                     const bool rotated)
  {
    const auto                         &body = scene.body();
    std::vector<warpchol::fem::Matrix3> rotations;
    if (rotated)
      body.compute_element_rotations(positions, rotations);
    std::vector<warpchol::fem::Vector3> forces(body.n_vertices(), warpchol::fem::Vector3::Zero());
    body.add_elastic_forces(positions, rotated ? &rotations : nullptr, forces);
    return forces;
  }

  /** The mean norm of the strain sym(G) of the elements whose stiffness changed. */
  double changed_strain(const warpchol::app::Scene &scene, const bool rotated)
  {
    const auto &body = scene.body();
    double      sum  = 0;
    unsigned    n    = 0;
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      if (body.element_stiffness_scale(e) != 1)
        {
          const warpchol::fem::Matrix3 g = body.displacement_gradient(e, scene.integrator().positions(), rotated);
          sum += (0.5 * (g + g.transpose())).norm();
          ++n;
        }
    return sum / n;
  }
} // namespace

int main()
{
  const std::vector<std::pair<std::string, std::string>> models{
    {"warp_canceling", "  set Type = warp_canceling\n  set Rerotation threshold = 0.3\n"},
    {"corotational", "  set Type = corotational\n"},
    {"linear", "  set Type = linear\n"}};

  for (const auto &[name, model] : models)
    for (const std::string stress : {"continuous", "reset"})
      {
        tests::write_file("run.prm", scene(model, 0.1, stress));
        warpchol::app::Simulation simulation{warpchol::app::AllParameters("run.prm")};
        std::ostringstream         summary;
        std::string                outcome;
        try
          {
            simulation.run(summary);
            outcome = std::to_string(simulation.totals(0).steps) + " steps";
          }
        catch (const warpchol::Error &error)
          {
            outcome = error.what();
          }
        std::cout << name << ", " << stress << ": " << outcome << std::endl;
      }

  for (const auto &[name, model] : models)
    {
      std::cout << name << ":" << std::endl;
      const bool rotated = name != "linear";
      tests::write_file("unchanged.prm", scene(model, 1e9, "continuous"));
      tests::write_file("continuous.prm", scene(model, 0.1, "continuous"));
      tests::write_file("reset.prm", scene(model, 0.1, "reset"));
      warpchol::app::Scene unchanged{warpchol::app::AllParameters("unchanged.prm")};
      warpchol::app::Scene continuous{warpchol::app::AllParameters("continuous.prm")};
      warpchol::app::Scene reset{warpchol::app::AllParameters("reset.prm")};
      advance(unchanged, 10);
      advance(continuous, 10);
      advance(reset, 10);
      const auto before = unchanged.integrator().positions();
      tests::check("  before the change, continuous and reset equal the run without it, to the bit",
                   continuous.integrator().positions() == before && reset.integrator().positions() == before &&
                     continuous.integrator().velocities() == unchanged.integrator().velocities() &&
                     reset.integrator().velocities() == unchanged.integrator().velocities());

      // The step of the change: its element pass evaluates the positions of step 10 with
      // the new material.
      const double                        energy_before = continuous.integrator().elastic_energy();
      const std::vector<warpchol::fem::Vector3> forces_before = elastic_forces(continuous, before, rotated);
      advance(continuous, 1);
      advance(reset, 1);
      const std::vector<warpchol::fem::Vector3> forces_after = elastic_forces(continuous, before, rotated);
      double largest = 0, difference = 0;
      for (std::size_t v = 0; v < forces_before.size(); ++v)
        {
          largest    = std::max(largest, forces_before[v].norm());
          difference = std::max(difference, (forces_after[v] - forces_before[v]).norm());
        }
      tests::check_below("  continuous: elastic forces at the change, after against before, relative",
                         difference / largest, 1e-6);
      const double continuous_change = continuous.integrator().change_energy();
      tests::check_below("  continuous: elastic energy after the change - (before + the change's energy), relative",
                         std::abs(continuous.integrator().elastic_energy_at_step_start() -
                                  (energy_before + continuous_change)) / energy_before,
                         1e-9);
      tests::check("  continuous: the change takes energy out, at most the energy held",
                   continuous_change < 0 && -continuous_change < energy_before);
      const double reset_change = reset.integrator().change_energy();
      tests::check_below("  reset: elastic energy after the change - (before + the change's energy), relative",
                         std::abs(reset.integrator().elastic_energy_at_step_start() - (energy_before + reset_change)) /
                           reset_change,
                         1e-9);
      tests::check("  reset: the change's energy is a jump of over 1000 times the energy held",
                   reset_change > 1e3 * energy_before);

      // The strain of the stiffened region at the change and 19 steps later.
      const double strain_at_change = changed_strain(continuous, rotated);
      advance(continuous, 19);
      advance(reset, 19);
      // Reset springs back as fast as Rayleigh's stiffness damping lets it: overdamped,
      // the strain decays as exp(-t / 0.1 s), to 0.15 in the 0.19 s left.
      tests::check("  continuous: the stiffened region holds its strain (over 0.9 of it at the end)",
                   changed_strain(continuous, rotated) > 0.9 * strain_at_change);
      tests::check("  reset: the stiffened region springs back (under 0.2 of its strain at the end)",
                   changed_strain(reset, rotated) < 0.2 * strain_at_change);
    }
}
