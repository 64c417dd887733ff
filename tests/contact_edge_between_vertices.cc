// A rigid wedge's edge narrower than the mesh's spacing: a triangle surface (a prism whose
// two slanted faces meet at 53 degrees along a 4 cm edge) comes down edge first on the top
// face of a block of one hexahedron (10 x 10 x 5 cm, 24 tetrahedra) between its vertices
// (the nearest is 3 cm away), presses 4 mm in and lifts off. The vertices alone would let
// the edge pass through; the points of the top triangles nearest the surface's sharp edges
// are contacts (their rows touch the triangles' 3 vertices by their barycentric weights),
// so the block's top is pushed down, the wedge pushed back, and no step leaves more
// penetration than the tolerance. A box's edges are found the same way: an axis-aligned box
// has 12.

#include <warpchol/contact/contact_constraints.h>
#include <warpchol/dynamics/implicit_euler.h>
#include <warpchol/mesh/mesh_generators.h>
#include <warpchol/models/corotational_model.h>

#include "contact_tests.h"
#include "tests.h"

#include <deal.II/grid/tria.h>

#include <Eigen/Geometry>

#include <cmath>

using namespace warpchol;
using fem::Vector3;

namespace
{
  /** A prism over the triangle (y, z): (0.02, z0), (0.01, z0 + 0.02), (0.03, z0 + 0.02), from x = 0.03 to 0.07, facing out. */
  fem::TriangleSurface wedge(const double z0)
  {
    fem::TriangleSurface surface;
    for (const double x : {0.03, 0.07})
      for (const auto &[y, z] : {std::pair{0.02, z0}, {0.01, z0 + 0.02}, {0.03, z0 + 0.02}})
        surface.points.emplace_back(x, y, z);
    // The two ends, then the three sides as two triangles each.
    surface.triangles = {{0, 1, 2}, {3, 5, 4}, {0, 3, 4}, {0, 4, 1}, {0, 2, 5}, {0, 5, 3}, {1, 4, 5}, {1, 5, 2}};
    // Outward: away from the prism's centre.
    Vector3 centre = Vector3::Zero();
    for (const Vector3 &p : surface.points)
      centre += p / 6;
    for (auto &t : surface.triangles)
      {
        const Vector3 &a = surface.points[t[0]], &b = surface.points[t[1]], &c = surface.points[t[2]];
        if ((b - a).cross(c - a).dot((a + b + c) / 3 - centre) < 0)
          std::swap(t[1], t[2]);
      }
    return surface;
  }
} // namespace

int main()
{
  std::cout << "sharp edges: an axis-aligned box " << fem::Obstacle::box(Vector3::Zero(), Vector3(1, 2, 3)).sharp_edges(0).size()
            << ", the wedge " << fem::Obstacle::surface(wedge(0)).sharp_edges(0).size() << std::endl;

  constexpr double tolerance = 1e-5;
  // The edge along x at y = 0.02, 2 mm above the top face, over its triangle (0, 0), (0.1, 0), (0.05, 0.05).
  fem::Obstacle blade = fem::Obstacle::surface(wedge(0.05 + 0.002));
  blade.set_path(fem::InstrumentPath({0, 0.2, 0.4, 1}, {0, 0, 0, 0, 0, -0.006, 0, 0, 0, 0, 0, 0}, 3));
  const tests::PressedTop pressed = tests::press_block_top(blade, tolerance);
  tests::check("the edge touched points inside the top triangles", pressed.points_in_triangles > 0);
  tests::check("no vertex touched it", pressed.vertex_contacts == 0);
  tests::check("the wedge is pushed back at its deepest (step 20)", pressed.force_at_depth > 0);
  tests::check("the block's top is pushed down by more than 3 mm", pressed.deepest_push < -0.003);
  tests::check_below("largest penetration over the steps (m)", pressed.largest_penetration, tolerance);
  tests::check("no contact once it has left (step 50)", !pressed.touching_at_end);
}
