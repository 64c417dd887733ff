// An instrument's tip smaller than the mesh's spacing: a sphere of radius 5 mm comes down
// on the top face of a block of one hexahedron (10 x 10 x 5 cm, 24 tetrahedra) between
// its vertices (the nearest is 3 cm away), presses 4 mm in and lifts off. The vertices
// alone would let it pass through; the point of the top triangle nearest the tip is a
// contact (its rows touch the triangle's 3 vertices by their barycentric weights), so the
// block's top is pushed down, the sphere pushed back, and no step leaves more
// penetration than the tolerance.

#include <warpchol/contact/contact_constraints.h>
#include <warpchol/dynamics/implicit_euler.h>
#include <warpchol/mesh/mesh_generators.h>
#include <warpchol/models/corotational_model.h>

#include "contact_tests.h"
#include "tests.h"

#include <deal.II/grid/tria.h>

#include <cmath>

using namespace warpchol;

int main()
{
  constexpr double         time_step = 0.01, tolerance = 1e-5;
  dealii::Triangulation<3> triangulation;
  fem::BoxGeometry         geometry;
  geometry.upper_corner = dealii::Point<3>(0.1, 0.1, 0.05);
  fem::create_box(triangulation, geometry);
  fem::ElasticBody body(triangulation, fem::Material{1e4, 0.3, 1000}, fem::MassMatrix::lumped,
                        tests::held_at_bottom(triangulation));
  const fem::Loads                   loads;
  cholesky::SparseCholesky::Settings solver;
  solver.method = cholesky::FactorizationMethod::supernodal;
  fem::CorotationalModel model(body, fem::ImplicitEuler::coefficients(body, time_step, 0.1, 0.01, loads), solver);
  fem::ImplicitEuler     integrator(body, model, loads, time_step);

  // Over the top face's triangle (0, 0), (0.1, 0), (0.05, 0.05), 2 mm above it.
  fem::Obstacle tip = fem::Obstacle::sphere(fem::Vector3(0.05, 0.02, 0.05 + 0.005 + 0.002), 0.005);
  tip.set_path(fem::InstrumentPath({0, 0.2, 0.4, 1}, {0, 0, 0, 0, 0, -0.006, 0, 0, 0, 0, 0, 0}, 3));
  fem::ContactSettings settings;
  settings.tolerance                   = tolerance;
  settings.gauss_seidel.max_iterations = 1000;
  settings.gauss_seidel.tolerance      = 1e-12;
  integrator.set_contact(fem::ContactConstraints({tip}, settings));

  double       largest_penetration = 0, deepest_push = 0, force_at_depth = 0;
  unsigned int points_in_triangles = 0, vertex_contacts = 0;
  for (unsigned int step = 0; step < 50; ++step)
    {
      fem::StepStatistics statistics;
      integrator.advance(statistics);
      const fem::ContactConstraints &contact = *integrator.contact();
      largest_penetration = std::max(largest_penetration, contact.last_step().largest_penetration);
      for (const fem::Contact &c : contact.contacts())
        (c.n_vertices == 3 ? points_in_triangles : vertex_contacts) += 1;
      if (step == 19)
        {
          force_at_depth = -contact.last_step().total_force[2];
          for (unsigned int v = 0; v < body.n_vertices(); ++v)
            deepest_push = std::min(deepest_push, integrator.displacements()[v][2]);
        }
    }
  tests::check("the tip touched points inside the top triangle", points_in_triangles > 0);
  tests::check("no vertex touched it", vertex_contacts == 0);
  tests::check("the sphere is pushed back at its deepest (step 20)", force_at_depth > 0);
  tests::check("the block's top is pushed down by more than 3 mm", deepest_push < -0.003);
  tests::check_below("largest penetration over the steps (m)", largest_penetration, tolerance);
  tests::check("no contact once it has left (step 50)", integrator.contact()->contacts().empty());
}
