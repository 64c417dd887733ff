// Penalty contact (Contact/Method = penalty): a block (0.1 x 0.1 x 0.05 m, 1000 kg/m^3)
// thrown up from a rigid plane falls back onto it. The vertices of its bottom face tie
// their springs as they land, and A's diagonal carries dt^2 k at them and nowhere else
// (the change the factor takes as an update). Once the block rests, the springs carry
// its weight to 1e-6 relative, and since each pushes k times its penetration, the mean
// penetration of the bottom vertices is m g / (n k). The energy balance, with the
// springs' work on the body counted as contact work, holds.

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

int main()
{
  constexpr double g = 9.81, time_step = 0.01, stiffness = 2e4;
  dealii::Triangulation<3> triangulation;
  fem::ElasticBody         body = tests::free_block(triangulation);
  fem::Loads loads;
  loads.gravity = Vector3(0, 0, -g);
  cholesky::SparseCholesky::Settings solver;
  solver.method          = cholesky::FactorizationMethod::supernodal;
  solver.ordering.method = cholesky::OrderingMethod::metis;
  fem::LinearModel   model(body, fem::ImplicitEuler::coefficients(body, time_step, 0, 0.01, loads), solver);
  fem::ImplicitEuler integrator(body, model, loads, time_step);
  integrator.set_initial_velocities(std::vector<Vector3>(body.n_vertices(), Vector3(0, 0, 0.2)));

  fem::ContactSettings settings;
  settings.method            = fem::ContactMethod::penalty;
  settings.penalty_stiffness = stiffness;
  integrator.set_contact(fem::ContactConstraints({fem::Obstacle::plane(Vector3::Zero(), Vector3::UnitZ())}, settings));

  fem::EnergyBalance balance(body);
  balance.record(integrator);
  unsigned int first_spring_step = 0, bottom = 0, a_bottom_vertex = 0;
  for (unsigned int v = 0; v < body.n_vertices(); ++v)
    if (body.rest_positions()[v][2] == 0)
      a_bottom_vertex = v, ++bottom;
  for (unsigned int step = 1; step <= 300; ++step)
    {
      fem::StepStatistics statistics;
      integrator.advance(statistics);
      balance.record(integrator);
      if (first_spring_step == 0 && model.vertex_diagonal(a_bottom_vertex) > 0)
        first_spring_step = step;
    }
  const fem::ContactStepReport &report = integrator.contact()->last_step();
  const double                  weight = body.total_mass() * g;
  unsigned int                  tied = 0, tied_elsewhere = 0;
  double                        mean_penetration = 0;
  for (unsigned int v = 0; v < body.n_vertices(); ++v)
    {
      const bool on_bottom = body.rest_positions()[v][2] == 0;
      const bool spring    = std::abs(model.vertex_diagonal(v) - time_step * time_step * stiffness) <= 1e-12;
      tied += on_bottom && spring ? 1 : 0;
      tied_elsewhere += !on_bottom && model.vertex_diagonal(v) != 0 ? 1 : 0;
      if (on_bottom)
        mean_penetration -= integrator.positions()[v][2] / bottom;
    }
  std::cout << "a block thrown up at 0.2 m/s lands on the plane, " << bottom << " vertices on its bottom" << std::endl;
  tests::check("  no spring before it lands (step > 2)", first_spring_step > 2);
  tests::check("  every bottom vertex carries dt^2 k on A's diagonal", tied == bottom);
  tests::check("  no other vertex carries a spring", tied_elsewhere == 0);
  tests::check_below("  |sum of normal forces - m g| / (m g)", std::abs(report.total_force[2] - weight) / weight, 1e-6);
  tests::check_below("  |mean penetration n k / (m g) - 1|",
                     std::abs(mean_penetration * bottom * stiffness / weight - 1), 1e-6);
  tests::check_below("  energy held / put in", balance.max_ratio(), 1 + 1e-9);
}
