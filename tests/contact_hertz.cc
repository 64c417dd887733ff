// Contact against Hertz's law: a rigid frictionless sphere of radius R = 10 cm pressed
// d = 0.4, 0.7 and 1 mm into a block (E 10 kPa, nu 0.3, held at its bottom) pushes back
// with Hertz's force F = 4/3 E* sqrt(R) d^(3/2), E* = E / (1 - nu^2) (a rigid indenter on
// an elastic half-space), within 10 % at each depth, and the force grows as d^(3/2)
// (the slope of log F against log d between the shallowest and the deepest within 0.1 of
// 3/2). Small strain: d / R <= 1 %, the linear model.
//
// The half-space: the contact radius a = sqrt(R d) is 6.3-10 mm, the block 80 cm wide and
// 40 cm deep (40 times the largest a). How fine the mesh is under the sphere: cubes of
// h = 2 mm (a / h = 3.2-5, 6-10 cubes across the contact's diameter), each split into 6
// tetrahedra, over 12 mm around the axis and 10 mm down; then cells growing by a factor
// 1.5 to the block's sides and bottom (the tensor grid's strips keep 2 mm across in one
// direction). The hexahedra of each quadrant are split about diagonals mirrored at the
// axis, so that the mesh under the sphere is symmetric. The block pushes back harder than
// Hertz's half-space, by what the linear tetrahedra and the held bottom add: finer cubes
// (1.2 mm) or a gentler grading remove about 2 % of it, not more.
//
// The indentation is quasi-static: a light block (1 kg/m^3), time steps of 1 s, the sphere
// moved to each depth in one step and held there for three more; the force is read in
// the last one, when Gauss-Seidel's warm start already satisfies the contacts.

#include <warpchol/contact/contact_constraints.h>
#include <warpchol/dynamics/implicit_euler.h>
#include <warpchol/mesh/mesh_readers.h>
#include <warpchol/models/linear_model.h>

#include "contact_tests.h"
#include "tests.h"

#include <deal.II/grid/tria.h>

#include <Eigen/Geometry>

#include <cmath>

using namespace warpchol;
using fem::Vector3;

namespace
{
  constexpr double radius = 0.1, youngs_modulus = 1e4, poisson_ratio = 0.3;
  constexpr double half_width = 0.4, depth = 0.4;
  /** The fine cubes under the sphere: their size and how many of them from the axis outward and downward. */
  constexpr double       fine_size         = 2e-3;
  constexpr unsigned int fine_cells_across = 6, fine_cells_down = 5;
  constexpr double       growth            = 1.5;
  constexpr double       time_step = 1;
  constexpr unsigned int steps_per_depth = 4;
  const std::vector<double> depths{0.4e-3, 0.7e-3, 1e-3};

  /**
   * The cell boundaries from 0 to @p length: @p n_fine cells of @p fine_size, then cells
   * growing by @p growth, the growing ones scaled so that the last ends at @p length.
   */
  std::vector<double> graded_coordinates(const unsigned int n_fine, const double length)
  {
    std::vector<double> coordinates{0};
    for (unsigned int i = 0; i < n_fine; ++i)
      coordinates.push_back(coordinates.back() + fine_size);
    std::vector<double> growing;
    double              sum = 0;
    for (double size = fine_size * growth; sum < length - coordinates.back(); size *= growth)
      growing.push_back(size), sum += size;
    const double scale = (length - coordinates.back()) / sum;
    for (const double size : growing)
      coordinates.push_back(coordinates.back() + scale * size);
    coordinates.back() = length; // exactly: the bottom's vertices are found by z == 0
    return coordinates;
  }

  /**
   * The block [-half_width, half_width]^2 x [0, depth], its top at z = depth: the graded
   * grid (fine around the z axis and under the top) split into tetrahedra by Kuhn's split
   * of each hexahedron, its diagonal mirrored at the planes x = 0 and y = 0 (the shared
   * faces of two hexahedra are split alike on either side, so the mesh is conforming).
   */
  fem::TetrahedralMesh graded_block()
  {
    const std::vector<double> outward = graded_coordinates(fine_cells_across, half_width);
    const std::vector<double> downward = graded_coordinates(fine_cells_down, depth);
    std::vector<double>       lateral;
    for (auto x = outward.rbegin(); x != outward.rend(); ++x)
      lateral.push_back(-*x);
    lateral.insert(lateral.end(), outward.begin() + 1, outward.end());
    std::vector<double> vertical;
    for (auto z = downward.rbegin(); z != downward.rend(); ++z)
      vertical.push_back(depth - *z);

    fem::TetrahedralMesh mesh;
    mesh.name              = "graded block";
    const unsigned int nx  = static_cast<unsigned int>(lateral.size()), nz = static_cast<unsigned int>(vertical.size());
    for (unsigned int k = 0; k < nz; ++k)
      for (unsigned int j = 0; j < nx; ++j)
        for (unsigned int i = 0; i < nx; ++i)
          mesh.vertices.push_back({{lateral[i], lateral[j], vertical[k]}});
    const auto vertex = [&](const std::array<unsigned int, 3> &c) { return c[0] + nx * (c[1] + nx * c[2]); };
    const unsigned int orders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    const unsigned int axis_cell    = (nx - 1) / 2;
    for (unsigned int k = 0; k + 1 < nz; ++k)
      for (unsigned int j = 0; j + 1 < nx; ++j)
        for (unsigned int i = 0; i + 1 < nx; ++i)
          for (const auto &order : orders)
            {
              // Start at the hexahedron's corner nearest the axis, step away from it.
              const std::array<bool, 3> mirrored{{i < axis_cell, j < axis_cell, false}};
              std::array<unsigned int, 3> corner{{i + mirrored[0], j + mirrored[1], k}};
              std::array<unsigned int, 4> tetrahedron{};
              tetrahedron[0] = vertex(corner);
              for (unsigned int a = 0; a < 3; ++a)
                {
                  corner[order[a]] = mirrored[order[a]] ? corner[order[a]] - 1 : corner[order[a]] + 1;
                  tetrahedron[a + 1] = vertex(corner);
                }
              mesh.tetrahedra.push_back(tetrahedron);
              mesh.locations.push_back("tetrahedron " + std::to_string(mesh.tetrahedra.size() - 1));
            }
    // Half of the tetrahedra come out negatively oriented: check_and_orient() turns them.
    for (auto &tetrahedron : mesh.tetrahedra)
      {
        const auto   &p = mesh.vertices;
        const Vector3 a(p[tetrahedron[0]].data()), b(p[tetrahedron[1]].data()), c(p[tetrahedron[2]].data()),
          d(p[tetrahedron[3]].data());
        if ((b - a).cross(c - a).dot(d - a) < 0)
          std::swap(tetrahedron[2], tetrahedron[3]);
      }
    return mesh;
  }

  /** Hertz's force (N) of a rigid sphere of radius R pressed @p indentation (m) into an elastic half-space. */
  double hertz_force(const double indentation)
  {
    const double effective_modulus = youngs_modulus / (1 - poisson_ratio * poisson_ratio);
    return 4. / 3. * effective_modulus * std::sqrt(radius) * std::pow(indentation, 1.5);
  }
} // namespace

int main()
{
  dealii::Triangulation<3> triangulation;
  fem::create_triangulation(graded_block(), triangulation);
  fem::ElasticBody body(triangulation, fem::Material{youngs_modulus, poisson_ratio, 1}, fem::MassMatrix::lumped,
                        tests::held_at_bottom(triangulation));
  std::cout << "block: " << body.n_elements() << " tetrahedra, " << body.n_vertices() << " vertices" << std::endl;

  const fem::Loads                   loads;
  cholesky::SparseCholesky::Settings solver;
  solver.method          = cholesky::FactorizationMethod::supernodal;
  solver.ordering.method = cholesky::OrderingMethod::metis;
  fem::LinearModel   model(body, fem::ImplicitEuler::coefficients(body, time_step, 0, 0, loads), solver);
  fem::ImplicitEuler integrator(body, model, loads, time_step);

  // The sphere touches the top's centre at time 0, goes down to each depth in one step
  // and stays there for the rest of the depth's steps.
  std::vector<double> times{0}, offsets{0, 0, 0};
  for (std::size_t k = 0; k < depths.size(); ++k)
    for (const double time : {k * steps_per_depth + 1., (k + 1.) * steps_per_depth})
      {
        times.push_back(time * time_step);
        offsets.insert(offsets.end(), {0, 0, -depths[k]});
      }
  fem::Obstacle sphere = fem::Obstacle::sphere(Vector3(0, 0, depth + radius), radius);
  sphere.set_path(fem::InstrumentPath(times, offsets, 3));
  fem::ContactSettings settings;
  settings.margin                      = 1e-5;
  settings.tolerance                   = 1e-6;
  settings.max_contacts                = 2000;
  settings.gauss_seidel.max_iterations = 5000;
  settings.gauss_seidel.tolerance      = 1e-12;
  integrator.set_contact(fem::ContactConstraints({sphere}, settings));

  std::vector<double> forces;
  for (std::size_t k = 0; k < depths.size(); ++k)
    {
      for (unsigned int step = 0; step < steps_per_depth; ++step)
        {
          fem::StepStatistics statistics;
          integrator.advance(statistics);
        }
      const fem::ContactStepReport &report = integrator.contact()->last_step();
      // The force on the sphere: minus the contacts' force on the block.
      forces.push_back(-report.total_force[2]);
      const double ratio = forces.back() / hertz_force(depths[k]);
      std::cout << "d = " << depths[k] * 1e3 << " mm (a = " << format_number(std::sqrt(radius * depths[k]) * 1e3, 2)
                << " mm): " << report.n_contacts << " contacts, F / F_Hertz = " << format_number(ratio, 3) << std::endl;
      tests::check_below("  |F / F_Hertz - 1|", std::abs(ratio - 1), 0.1);
      tests::check("  Gauss-Seidel converged", report.gauss_seidel.converged);
      tests::check_below("  largest penetration (m)", report.largest_penetration, settings.tolerance);
    }
  const double slope = std::log(forces.back() / forces.front()) / std::log(depths.back() / depths.front());
  tests::check_below("|slope of log F against log d - 3/2|", std::abs(slope - 1.5), 0.1);
}
