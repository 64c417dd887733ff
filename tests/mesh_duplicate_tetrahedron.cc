// A mesh file that lists the same tetrahedron twice (the same four vertices, in any order)
// is refused in one line naming both cells, whatever the format: the element's stiffness
// and mass would count twice. The program exits with status 2. Cells that share three
// vertices (neighbours) are not repetitions.

#include "simulation_tests.h"

#include <warpchol/mesh/mesh_readers.h>

#include <fstream>
#include <iomanip>

using namespace warpchol;

namespace
{
  void read(const std::string &label, const std::string &filename)
  {
    tests::print_result_or_error(label, [&] {
      dealii::Triangulation<3> triangulation;
      fem::read_mesh(filename, triangulation);
      return std::to_string(triangulation.n_active_cells()) + " tets";
    });
  }

  /** Gmsh 1: two neighbours sharing a face, then @p more element lines. */
  std::string gmsh(const std::string &more, const unsigned int n_more)
  {
    return "$NOD\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n$ENDNOD\n$ELM\n" +
           std::to_string(2 + n_more) + "\n1 4 1 1 4 1 2 3 4\n2 4 1 1 4 2 3 4 5\n" + more + "$ENDELM\n";
  }
} // namespace

int main()
{
  tests::write_file("neighbours.msh", gmsh("", 0));
  read("two neighbours", "neighbours.msh");
  // Element 1 again, its vertices turned (same orientation) and mirrored (opposite).
  tests::write_file("turned.msh", gmsh("3 4 1 1 4 2 3 1 4\n", 1));
  read("element 1 again, vertices turned", "turned.msh");
  tests::write_file("mirrored.msh", gmsh("3 4 1 1 4 1 3 2 4\n", 1));
  read("element 1 again, mirrored", "mirrored.msh");
  tests::write_file("three_times.msh", gmsh("3 4 1 1 4 2 3 4 5\n4 4 1 1 4 5 3 4 2\n", 2));
  read("element 2 three times", "three_times.msh");

  tests::write_file("repeated.vtk", "# vtk DataFile Version 3.0\nrepeated cell\nASCII\n"
                                    "DATASET UNSTRUCTURED_GRID\nPOINTS 5 double\n"
                                    "0 0 0  1 0 0  0 1 0  0 0 1  1 1 1\n"
                                    "CELLS 3 15\n4 0 1 2 3\n4 1 2 3 4\n4 1 2 3 0\n"
                                    "CELL_TYPES 3\n10\n10\n10\n");
  read("legacy VTK, cell 0 again", "repeated.vtk");

  // SOFA's liver with its first tetrahedron appended: the program refuses it.
  {
    const auto    liver = fem::read_gmsh(std::string(SOURCE_DIR) + "/../meshes/sofa_liver.msh");
    std::ofstream file("liver_repeated.msh");
    file << std::setprecision(17) << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n"
         << liver.vertices.size() << "\n";
    for (std::size_t v = 0; v < liver.vertices.size(); ++v)
      file << v + 1 << " " << liver.vertices[v][0] << " " << liver.vertices[v][1] << " "
           << liver.vertices[v][2] << "\n";
    file << "$EndNodes\n$Elements\n" << liver.tetrahedra.size() + 1 << "\n";
    for (std::size_t t = 0; t <= liver.tetrahedra.size(); ++t)
      {
        const auto &tetrahedron = liver.tetrahedra[t % liver.tetrahedra.size()];
        file << t + 1 << " 4 2 0 1 " << tetrahedron[0] + 1 << " " << tetrahedron[1] + 1 << " "
             << tetrahedron[2] + 1 << " " << tetrahedron[3] + 1 << "\n";
      }
    file << "$EndElements\n";
    std::cout << "SOFA's liver: " << liver.tetrahedra.size() << " tets in the file, the first once more"
              << std::endl;
  }
  tests::write_file("liver_repeated.prm", "subsection Mesh\n  set Source = file\n  set File = liver_repeated.msh\nend\n"
                                          "subsection Time stepping\n  set Number of steps = 1\nend\n");
  std::cout << "warpchol liver_repeated.prm: " << tests::run_warpchol({"liver_repeated.prm"}) << std::endl;
}
