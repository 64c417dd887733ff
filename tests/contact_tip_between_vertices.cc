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
  constexpr double tolerance = 1e-5;
  // Over the top face's triangle (0, 0), (0.1, 0), (0.05, 0.05), 2 mm above it.
  fem::Obstacle tip = fem::Obstacle::sphere(fem::Vector3(0.05, 0.02, 0.05 + 0.005 + 0.002), 0.005);
  tip.set_path(fem::InstrumentPath({0, 0.2, 0.4, 1}, {0, 0, 0, 0, 0, -0.006, 0, 0, 0, 0, 0, 0}, 3));
  const tests::PressedTop pressed = tests::press_block_top(tip, tolerance);
  tests::check("the tip touched points inside the top triangle", pressed.points_in_triangles > 0);
  tests::check("no vertex touched it", pressed.vertex_contacts == 0);
  tests::check("the sphere is pushed back at its deepest (step 20)", pressed.force_at_depth > 0);
  tests::check("the block's top is pushed down by more than 3 mm", pressed.deepest_push < -0.003);
  tests::check_below("largest penetration over the steps (m)", pressed.largest_penetration, tolerance);
  tests::check("no contact once it has left (step 50)", !pressed.touching_at_end);
}
