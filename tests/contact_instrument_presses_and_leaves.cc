// A moving instrument: a sphere (radius 2 cm) on a path comes down on a block (10 x 10 x
// 5 cm, E 10 kPa, held at its bottom), presses 5 mm into it and lifts off again. Contacts
// appear when it arrives and all disappear once it has left; no step leaves more
// penetration than the tolerance; the block pushes back harder the deeper the sphere is;
// the sphere's work is counted in the energy balance (held <= put in). The same run with
// SOFA's way of building W (Contact/Compliance = full solves) gives the same velocities
// (step 18, pressing) to 1e-10 relative as W by paths renewed at every change of the
// factor. The checks of the run hold with W lagging behind the factor (Compliance lag;
// the corotational model refactors every step), its velocities within 1e-3.

#include <warpchol/contact/contact_constraints.h>
#include <warpchol/dynamics/energy_balance.h>
#include <warpchol/dynamics/implicit_euler.h>
#include <warpchol/mesh/mesh_generators.h>
#include <warpchol/models/corotational_model.h>

#include "contact_tests.h"
#include "tests.h"

#include <deal.II/grid/tria.h>

#include <cmath>

using namespace warpchol;

namespace
{
  constexpr double time_step = 0.01, tolerance = 1e-5;

  struct Run
  {
    std::vector<unsigned int> contacts;
    std::vector<double>       force, penetration;
    double                    max_energy_ratio = 0, obstacle_work = 0;
    std::vector<fem::Vector3> velocities;
    unsigned int              largest_lag = 0;
  };

  Run press(const cholesky::ComplianceMethod compliance, const bool lag)
  {
    dealii::Triangulation<3> triangulation;
    fem::BoxGeometry         geometry;
    geometry.upper_corner = dealii::Point<3>(0.1, 0.1, 0.05);
    geometry.subdivisions = {{4, 4, 2}};
    fem::create_box(triangulation, geometry);
    fem::ElasticBody body(triangulation, fem::Material{1e4, 0.3, 1000}, fem::MassMatrix::lumped,
                          tests::held_at_bottom(triangulation));
    const fem::Loads                   loads;
    cholesky::SparseCholesky::Settings solver;
    solver.method          = cholesky::FactorizationMethod::supernodal;
    solver.ordering.method = cholesky::OrderingMethod::metis;
    fem::CorotationalModel model(body, fem::ImplicitEuler::coefficients(body, time_step, 0.1, 0.01, loads), solver);
    fem::ImplicitEuler     integrator(body, model, loads, time_step);

    // 5 mm above the top, 5 mm into it at 0.2 s, back by 0.4 s.
    const fem::Vector3 start(0.05, 0.05, 0.05 + 0.02 + 0.005);
    fem::Obstacle      probe = fem::Obstacle::sphere(start, 0.02);
    probe.set_path(fem::InstrumentPath({0, 0.2, 0.4, 1}, {0, 0, 0, 0, 0, -0.01, 0, 0, 0, 0, 0, 0}, 3));
    probe.set_friction(0.3);
    fem::ContactSettings settings;
    settings.tolerance                   = tolerance;
    settings.gauss_seidel.max_iterations = 2000;
    settings.gauss_seidel.tolerance      = 1e-12;
    settings.compliance                  = compliance;
    settings.keep_compliance_across_factor_changes = lag;
    integrator.set_contact(fem::ContactConstraints({probe}, settings));

    fem::EnergyBalance balance(body);
    balance.record(integrator);
    Run run;
    for (unsigned int step = 0; step < 50; ++step)
      {
        fem::StepStatistics statistics;
        integrator.advance(statistics);
        balance.record(integrator);
        const fem::ContactStepReport &report = integrator.contact()->last_step();
        run.contacts.push_back(report.n_contacts);
        // The force on the sphere: minus the contact force on the block.
        run.force.push_back(-report.total_force[2]);
        run.penetration.push_back(report.largest_penetration);
        run.largest_lag = std::max(run.largest_lag, report.compliance_lag);
        if (step == 17)
          run.velocities = integrator.velocities();
      }
    run.max_energy_ratio = balance.max_ratio();
    return run;
  }
} // namespace

int main()
{
  const Run run = press(cholesky::ComplianceMethod::paths, true);
  // The steps with contacts form one stretch, within the path's motion.
  unsigned int first = 0, last = 0, stretches = 0;
  for (unsigned int step = 0; step < run.contacts.size(); ++step)
    if (run.contacts[step] > 0)
      {
        if (step == 0 || run.contacts[step - 1] == 0)
          ++stretches, first = step + 1;
        last = step + 1;
      }
  std::cout << "contacts from step " << first << " to step " << last << std::endl;
  tests::check("no contact in the first step, none in the last", run.contacts.front() == 0 && run.contacts.back() == 0);
  tests::check("one stretch of steps with contacts", stretches == 1);
  tests::check("contacts while the sphere is deepest (0.2 s, step 20)", run.contacts[19] > 0);
  double largest = 0;
  for (const double p : run.penetration)
    largest = std::max(largest, p);
  tests::check_below("largest penetration over the steps (m)", largest, tolerance);
  tests::check("the block pushes the sphere up while it presses (force > 0)", run.force[19] > 0);
  tests::check("harder at 5 mm (step 20) than at 2.5 mm on the way down (step 15)", run.force[19] > run.force[14]);
  tests::check_below("energy held / put in, the sphere's work counted", run.max_energy_ratio, 1 + 1e-6);

  const auto relative_difference = [](const Run &a, const Run &b) {
    double difference = 0, scale = 0;
    for (std::size_t v = 0; v < a.velocities.size(); ++v)
      {
        difference = std::max(difference, (a.velocities[v] - b.velocities[v]).norm());
        scale      = std::max(scale, b.velocities[v].norm());
      }
    return difference / scale;
  };
  const Run renewed = press(cholesky::ComplianceMethod::paths, false);
  const Run sofa    = press(cholesky::ComplianceMethod::full_solves, false);
  tests::check_below("max |v_paths - v_full solves| / max |v|", relative_difference(renewed, sofa), 1e-10);
  tests::check("W lagged behind the factor in some steps", run.largest_lag > 0);
  tests::check_below("max |v_lagged W - v_full solves| / max |v|", relative_difference(run, sofa), 1e-3);
}
