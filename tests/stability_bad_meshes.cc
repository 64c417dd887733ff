// Badly shaped meshes, every model: a box of slivers (Kuhn's 6 tetrahedra per hexahedron,
// flattened to 2 % of their volume along a direction no edge follows: flat tetrahedra
// without a short edge) and a box graded 100 times along every axis (element sizes span a
// factor 100). Each is held at one end (y = 0), pulled sideways by a tool at the other and
// by gravity. A row per case and model (stability_tests.h), the mesh's figures first, and
// the clean errors of meshes too flat to use.

#include "stability_tests.h"

#include <warpchol/mesh/mesh_generators.h>

#include <deal.II/grid/tria.h>

#include <cmath>

namespace
{
  std::string box_scene(const std::string &mesh_entries)
  {
    return "subsection Mesh\n  set Source = box\n  set Box lower corner = 0, 0, 0\n"
           "  set Box upper corner = 0.1, 0.4, 0.1\n" + mesh_entries + "end\n"
           "subsection Material\n  set Young's modulus = 500\nend\n"
           "subsection Time stepping\n  set Time step = 0.01\n  set Rayleigh mass = 0.1\n"
           "  set Rayleigh stiffness = 0.1\n  set Energy growth limit = 0\nend\n"
           "subsection Gravity\n  set Acceleration = 0, 0, -9.81\nend\n"
           "subsection Fixed vertices\n  set Region = box\n  set Box lower corner = -1, -1, -1\n"
           "  set Box upper corner = 1, 0.001, 1\nend\n"
           "subsection Tool\n  set Region = box\n  set Box lower corner = -1, 0.399, -1\n"
           "  set Box upper corner = 1, 1, 1\n  set Spring stiffness = 20\n"
           "  set Velocity = 0.5, 0, 0.5\n  set Duration = 0.3\nend\n";
  }

  /**
   * The worst shape, 6 sqrt 2 V / l_max^3 (1 for the regular tetrahedron, 0 for a flat one),
   * and the span of the element sizes (largest longest edge over the smallest).
   */
  void print_mesh_figures(const std::string &label, const warpchol::fem::BoxGeometry &geometry)
  {
    dealii::Triangulation<3> triangulation;
    warpchol::fem::create_box(triangulation, geometry);
    double worst_shape = 1, smallest = 1e300, largest = 0;
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        double longest = 0;
        for (unsigned int a = 0; a < 4; ++a)
          for (unsigned int b = a + 1; b < 4; ++b)
            longest = std::max(longest, cell->vertex(a).distance(cell->vertex(b)));
        const auto   e1 = cell->vertex(1) - cell->vertex(0), e2 = cell->vertex(2) - cell->vertex(0),
                   e3 = cell->vertex(3) - cell->vertex(0);
        const double volume = dealii::scalar_product(e1, dealii::cross_product_3d(e2, e3)) / 6;
        worst_shape         = std::min(worst_shape, 6 * std::sqrt(2.0) * volume / std::pow(longest, 3));
        smallest            = std::min(smallest, longest);
        largest             = std::max(largest, longest);
      }
    std::cout << label << ": " << triangulation.n_vertices() << " vertices, "
              << triangulation.n_active_cells() << " tets, worst shape 6 sqrt2 V / l^3 = "
              << warpchol::format_number(worst_shape, 2) << ", element sizes span "
              << warpchol::format_number(largest / smallest, 2) << std::endl;
  }
} // namespace

int main()
{
  warpchol::fem::BoxGeometry slivers{{0, 0, 0}, {0.1, 0.4, 0.1}, {{2, 8, 2}}, 1, 0.02};
  warpchol::fem::BoxGeometry graded{{0, 0, 0}, {0.1, 0.4, 0.1}, {{3, 8, 3}}, 100, 1};
  warpchol::fem::BoxGeometry regular{{0, 0, 0}, {0.1, 0.4, 0.1}, {{2, 8, 2}}, 1, 1};
  print_mesh_figures("regular box", regular);
  print_mesh_figures("sliver box", slivers);
  print_mesh_figures("graded box", graded);

  const std::vector<std::pair<std::string, std::string>> meshes = {
    {"regular box", "  set Box subdivisions = 2, 8, 2\n"},
    {"sliver box", "  set Box subdivisions = 2, 8, 2\n  set Box sliver flattening = 0.02\n"},
    {"graded box 100x", "  set Box subdivisions = 3, 8, 3\n  set Box grading = 100\n"}};
  for (const auto &[mesh, entries] : meshes)
    for (const auto &[label, model] : tests::stability_models())
      tests::print_stability_row(mesh, label, tests::run_stability_case(box_scene(entries), model, 200));

  tests::expect_error("flattening 0", [] {
    tests::write_file("flat.prm", "subsection Mesh\n  set Source = box\n  set Box sliver flattening = 0\nend\n");
    warpchol::app::AllParameters parameters("flat.prm");
  });
  tests::expect_error("flattening 1e-12", [] {
    tests::write_file("flat.prm", "subsection Mesh\n  set Source = box\n  set Box sliver flattening = 1e-12\nend\n");
    warpchol::app::Scene scene{warpchol::app::AllParameters("flat.prm")};
  });
}
