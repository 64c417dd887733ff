#pragma once

#include <warpchol/fem/elastic_body.h>
#include <warpchol/mesh/mesh_generators.h>

#include <deal.II/grid/tria.h>

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
} // namespace tests
