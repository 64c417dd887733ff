#pragma once

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
} // namespace tests
