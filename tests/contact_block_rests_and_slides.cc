// Contact against closed-form results: a block (0.1 x 0.1 x 0.05 m, 1000 kg/m^3) resting
// on a rigid plane under gravity carries its weight: after it settles the contact forces
// sum to m g to 1e-6 relative. On an incline (gravity tilted by theta; friction 0.5, the
// friction angle 26.57 degrees) friction holds it at 20 degrees (it moves by less than
// 0.1 mm in 0.5 s, where it would slide 42 cm without friction; only the lightly loaded
// edges of its bottom slip by microns) and lets it slide at 35 degrees with Coulomb's
// acceleration g (sin theta - mu cos theta) to 0.1 % (from 0.25 s to 0.5 s, once the
// block has settled on the slope). Every step leaves less penetration than the
// tolerance, and the energy balance (contact work counted) holds.

#include <warpchol/contact/contact_constraints.h>
#include <warpchol/dynamics/energy_balance.h>
#include <warpchol/dynamics/implicit_euler.h>
#include <warpchol/mesh/mesh_generators.h>
#include <warpchol/models/linear_model.h>

#include "contact_tests.h"
#include "tests.h"

#include <deal.II/grid/tria.h>

#include <cmath>

using namespace warpchol;
using fem::Vector3;

namespace
{
  constexpr double g = 9.81, time_step = 0.01, friction = 0.5, tolerance = 1e-5;

  /** What a run of the block measured. */
  struct Outcome
  {
    double  mass = 0;
    Vector3 contact_force;
    /** Mean displacement along x, and the mean velocity at the end and halfway. */
    double  mean_slip = 0;
    Vector3 mean_velocity, mean_velocity_halfway;
    double  largest_penetration = 0;
    double  max_energy_ratio    = 0;
    unsigned int contacts = 0, bottom_vertices = 0, max_gauss_seidel_iterations = 0;
  };

  Outcome run_block(const double tilt_degrees, const unsigned int n_steps)
  {
    dealii::Triangulation<3> triangulation;
    fem::ElasticBody         body = tests::free_block(triangulation);

    const double tilt = tilt_degrees * M_PI / 180;
    fem::Loads   loads;
    loads.gravity = Vector3(g * std::sin(tilt), 0, -g * std::cos(tilt));
    cholesky::SparseCholesky::Settings solver;
    solver.method          = cholesky::FactorizationMethod::supernodal;
    solver.ordering.method = cholesky::OrderingMethod::metis;
    fem::LinearModel   model(body, fem::ImplicitEuler::coefficients(body, time_step, 0, 0.01, loads), solver);
    fem::ImplicitEuler integrator(body, model, loads, time_step);

    fem::Obstacle table = fem::Obstacle::plane(Vector3::Zero(), Vector3::UnitZ());
    table.set_friction(friction);
    fem::ContactSettings settings;
    settings.tolerance                   = tolerance;
    settings.gauss_seidel.max_iterations = 5000;
    settings.gauss_seidel.tolerance      = 1e-13;
    integrator.set_contact(fem::ContactConstraints({table}, settings));

    fem::EnergyBalance balance(body);
    balance.record(integrator);
    Outcome outcome;
    outcome.mass = body.total_mass();
    for (unsigned int step = 0; step < n_steps; ++step)
      {
        fem::StepStatistics statistics;
        integrator.advance(statistics);
        balance.record(integrator);
        const fem::ContactStepReport &report = integrator.contact()->last_step();
        outcome.largest_penetration          = std::max(outcome.largest_penetration, report.largest_penetration);
        outcome.max_gauss_seidel_iterations  = std::max(outcome.max_gauss_seidel_iterations, report.gauss_seidel.iterations);
        if (2 * (step + 1) == n_steps)
          {
            outcome.mean_velocity_halfway = Vector3::Zero();
            for (unsigned int v = 0; v < body.n_vertices(); ++v)
              outcome.mean_velocity_halfway += integrator.velocities()[v] / body.n_vertices();
          }
      }
    const fem::ContactStepReport &report = integrator.contact()->last_step();
    outcome.contact_force                = report.total_force;
    outcome.contacts                     = report.n_contacts;
    outcome.mean_velocity                = Vector3::Zero();
    for (unsigned int v = 0; v < body.n_vertices(); ++v)
      {
        outcome.mean_velocity += integrator.velocities()[v] / body.n_vertices();
        if (body.rest_positions()[v][2] == 0)
          ++outcome.bottom_vertices;
        outcome.mean_slip += integrator.displacements()[v][0] / body.n_vertices();
      }
    outcome.max_energy_ratio = balance.max_ratio();
    return outcome;
  }
} // namespace

int main()
{
  {
    const Outcome rest = run_block(0, 200);
    std::cout << "resting block: " << rest.contacts << " contacts" << std::endl;
    tests::check("  every vertex of the bottom face touches, no other", rest.contacts == rest.bottom_vertices);
    tests::check_below("  |sum of normal forces - m g| / (m g)", std::abs(rest.contact_force[2] - rest.mass * g) / (rest.mass * g),
                       1e-6);
    tests::check_below("  |tangential force| / (m g)", rest.contact_force.template head<2>().norm() / (rest.mass * g), 1e-6);
    tests::check_below("  largest penetration (m)", rest.largest_penetration, tolerance);
    tests::check_below("  energy held / put in", rest.max_energy_ratio, 1 + 1e-9);
  }
  {
    const Outcome stick = run_block(20, 50);
    std::cout << "incline of 20 degrees, below the friction angle:" << std::endl;
    tests::check_below("  |mean displacement along the slope| (m)", std::abs(stick.mean_slip), 1e-4);
    tests::check_below("  |mean velocity| (m/s)", stick.mean_velocity.norm(), 1e-4);
    tests::check_below("  largest penetration (m)", stick.largest_penetration, tolerance);
  }
  {
    const double  tilt  = 35 * M_PI / 180;
    const Outcome slide    = run_block(35, 50);
    const double  expected = g * (std::sin(tilt) - friction * std::cos(tilt));
    const double  measured = (slide.mean_velocity[0] - slide.mean_velocity_halfway[0]) / (25 * time_step);
    std::cout << "incline of 35 degrees, above the friction angle:" << std::endl;
    tests::check("  it slides down the slope (mean velocity > 0.5 m/s)", slide.mean_velocity[0] > 0.5);
    tests::check_below("  |acceleration - g (sin - mu cos)| / g (sin - mu cos)", std::abs(measured - expected) / expected, 1e-3);
    tests::check_below("  largest penetration (m)", slide.largest_penetration, tolerance);
    tests::check_below("  energy held / put in", slide.max_energy_ratio, 1 + 1e-9);
  }
}
