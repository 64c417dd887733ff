#pragma once

#include <warpchol/contact/contact_constraints.h>
#include <warpchol/dynamics/implicit_euler.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/mesh/mesh_generators.h>
#include <warpchol/models/corotational_model.h>

#include <deal.II/grid/tria.h>

#include <algorithm>
#include <cmath>
#include <vector>

/**
 * @file
 * What the contact tests share: their blocks stand on the plane z = 0, held there, and
 * obstacles press them from above.
 */
namespace tests
{
  /** Per vertex of @p triangulation: whether it lies on z = 0 (held, fem::ElasticBody's fixed). */
  inline std::vector<bool> held_at_bottom(const dealii::Triangulation<3> &triangulation)
  {
    std::vector<bool> held(triangulation.n_vertices(), false);
    for (unsigned int v = 0; v < triangulation.n_vertices(); ++v)
      held[v] = triangulation.get_vertices()[v][2] == 0;
    return held;
  }

  /**
   * A block of 0.1 x 0.1 x 0.05 m (3 x 3 x 2 cubes) from the origin, E = 1e5 Pa, nu = 0.3,
   * 1000 kg/m^3, lumped masses, nothing held, on @p triangulation.
   */
  inline warpchol::fem::ElasticBody free_block(dealii::Triangulation<3> &triangulation)
  {
    warpchol::fem::BoxGeometry geometry;
    geometry.lower_corner = dealii::Point<3>(0, 0, 0);
    geometry.upper_corner = dealii::Point<3>(0.1, 0.1, 0.05);
    geometry.subdivisions = {{3, 3, 2}};
    warpchol::fem::create_box(triangulation, geometry);
    return warpchol::fem::ElasticBody(triangulation, warpchol::fem::Material{1e5, 0.3, 1000},
                                      warpchol::fem::MassMatrix::lumped,
                                      std::vector<bool>(triangulation.n_vertices(), false));
  }

  /** What press_block_top() measured. */
  struct PressedTop
  {
    double       largest_penetration = 0;
    /** At step 20: the force on the instrument (up) and the lowest displacement of the block. */
    double       force_at_depth = 0, deepest_push = 0;
    /** Contacts over the steps: points in surface triangles, and vertices. */
    unsigned int points_in_triangles = 0, vertex_contacts = 0;
    /**
     * The block's top corners' mean turn (rad, counter-clockwise seen from above) about
     * the vertical axis through the top's centre, the largest over the steps.
     */
    double       largest_turn = 0;
    bool         touching_at_end = true;
  };

  /**
   * A block of one hexahedron (10 x 10 x 5 cm, 24 tetrahedra, E = 10 kPa, held at its
   * bottom), corotational, pressed by @p instrument (on its path) for 50 steps of 10 ms:
   * constraints, Gauss-Seidel to 1e-12 m/s, the penetration's tolerance @p tolerance.
   */
  inline PressedTop press_block_top(const warpchol::fem::Obstacle &instrument, const double tolerance)
  {
    using namespace warpchol;
    constexpr double         time_step = 0.01;
    dealii::Triangulation<3> triangulation;
    fem::BoxGeometry         geometry;
    geometry.upper_corner = dealii::Point<3>(0.1, 0.1, 0.05);
    fem::create_box(triangulation, geometry);
    fem::ElasticBody body(triangulation, fem::Material{1e4, 0.3, 1000}, fem::MassMatrix::lumped,
                          held_at_bottom(triangulation));
    const fem::Loads                   loads;
    cholesky::SparseCholesky::Settings solver;
    solver.method = cholesky::FactorizationMethod::supernodal;
    fem::CorotationalModel model(body, fem::ImplicitEuler::coefficients(body, time_step, 0.1, 0.01, loads), solver);
    fem::ImplicitEuler     integrator(body, model, loads, time_step);
    fem::ContactSettings   settings;
    settings.tolerance                   = tolerance;
    settings.gauss_seidel.max_iterations = 1000;
    settings.gauss_seidel.tolerance      = 1e-12;
    integrator.set_contact(fem::ContactConstraints({instrument}, settings));

    PressedTop pressed;
    for (unsigned int step = 0; step < 50; ++step)
      {
        fem::StepStatistics statistics;
        integrator.advance(statistics);
        const fem::ContactConstraints &contact = *integrator.contact();
        pressed.largest_penetration = std::max(pressed.largest_penetration, contact.last_step().largest_penetration);
        for (const fem::Contact &c : contact.contacts())
          (c.n_vertices == 3 ? pressed.points_in_triangles : pressed.vertex_contacts) += 1;
        double                          turn          = 0;
        const std::vector<fem::Vector3> displacements = integrator.displacements();
        for (unsigned int v = 0; v < body.n_vertices(); ++v)
          {
            const auto &rest = triangulation.get_vertices()[v];
            if (rest[2] == 0.05 && (rest[0] == 0 || rest[0] == 0.1) && (rest[1] == 0 || rest[1] == 0.1))
              {
                const double        x = rest[0] - 0.05, y = rest[1] - 0.05;
                const fem::Vector3 &u = displacements[v];
                turn += std::atan2(x * (y + u[1]) - y * (x + u[0]), x * (x + u[0]) + y * (y + u[1])) / 4;
              }
          }
        if (std::abs(turn) > std::abs(pressed.largest_turn))
          pressed.largest_turn = turn;
        if (step == 19)
          {
            pressed.force_at_depth = -contact.last_step().total_force[2];
            for (unsigned int v = 0; v < body.n_vertices(); ++v)
              pressed.deepest_push = std::min(pressed.deepest_push, integrator.displacements()[v][2]);
          }
      }
    pressed.touching_at_end = !integrator.contact()->contacts().empty();
    return pressed;
  }
} // namespace tests
