#pragma once

#include <warpchol/mesh/mesh_generators.h>

#include <deal.II/grid/tria.h>

#include <array>
#include <vector>

/**
 * @file
 * What the assembly and solver tests share: a bar from the origin, held at its end x = 0.
 */
namespace tests
{
  /**
   * Fill @p triangulation with the tetrahedral box from the origin to @p upper_corner in
   * @p subdivisions cubes; returns per vertex whether it lies on x = 0 (held: fem::ElasticBody's
   * fixed).
   */
  inline std::vector<bool> bar_held_at_one_end(dealii::Triangulation<3> &triangulation,
                                               const dealii::Point<3>   &upper_corner,
                                               const std::array<unsigned int, 3> &subdivisions)
  {
    warpchol::fem::BoxGeometry box;
    box.upper_corner = upper_corner;
    box.subdivisions = subdivisions;
    warpchol::fem::create_box(triangulation, box);
    std::vector<bool> held(triangulation.n_vertices(), false);
    for (unsigned int v = 0; v < triangulation.n_vertices(); ++v)
      held[v] = triangulation.get_vertices()[v][0] < 1e-12;
    return held;
  }
} // namespace tests
