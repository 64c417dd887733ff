// The mesh readers: SOFA's Gmsh 1 files (non-contiguous node ids, lines and triangles to
// skip), Gmsh 2.2 (the same liver must come out identical), Gmsh 4.1, legacy VTK and VTU
// (through the VTK library), with unused vertices dropped and the file's vertex numbering
// kept for ids; files in the opposite orientation convention are reoriented.

#include "simulation_tests.h"

#include <warpchol/mesh/mesh_readers.h>

#include <iomanip>
#include <sstream>

using namespace warpchol;

namespace
{
  void describe(const std::string &name, const std::string &filename)
  {
    dealii::Triangulation<3> triangulation;
    const auto               numbering = fem::read_mesh(filename, triangulation);
    long                     dropped   = 0;
    for (const long v : numbering.vertex_of_file_vertex)
      dropped += v < 0;
    std::cout << name << ": " << triangulation.n_vertices() << " vertices, "
              << triangulation.n_active_cells() << " tets, " << dropped << " unused vertices dropped"
              << std::endl;
  }

  const std::string two_tetrahedra_points = "0 0 0  1 0 0  0 1 0  0 0 1  1 1 1  5 5 5";
} // namespace

int main()
{
  const std::string meshes = std::string(SOURCE_DIR) + "/../meshes/";
  describe("SOFA torus, Gmsh 1 (ids 1..447, lines, triangles)", meshes + "sofa_torus_low_res.msh");
  describe("SOFA liver, Gmsh 1", meshes + "sofa_liver.msh");
  describe("fine torus, Gmsh 2.2 (points, lines, triangles)", meshes + "torus_fine.msh");
  describe("SOFA raptor, VTU XML ASCII big-endian", meshes + "sofa_raptor_19409.vtu");

  // Gmsh 1 and 2.2 of the same liver: the same vertices in the same order, the same cells.
  tests::write_file("liver_v22.msh", [&] {
    const auto mesh = fem::read_gmsh(meshes + "sofa_liver.msh");
    std::ostringstream text;
    text << std::setprecision(17) << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n"
         << mesh.vertices.size() << "\n";
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
      text << v + 1 << " " << mesh.vertices[v][0] << " " << mesh.vertices[v][1] << " "
           << mesh.vertices[v][2] << "\n";
    text << "$EndNodes\n$Elements\n" << mesh.tetrahedra.size() << "\n";
    for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
      text << t + 1 << " 4 2 0 1 " << mesh.tetrahedra[t][0] + 1 << " " << mesh.tetrahedra[t][1] + 1
           << " " << mesh.tetrahedra[t][2] + 1 << " " << mesh.tetrahedra[t][3] + 1 << "\n";
    text << "$EndElements\n";
    return text.str();
  }());
  {
    dealii::Triangulation<3> v1, v22;
    fem::read_mesh(meshes + "sofa_liver.msh", v1);
    fem::read_mesh("liver_v22.msh", v22);
    bool same = v1.n_vertices() == v22.n_vertices() && v1.n_active_cells() == v22.n_active_cells();
    for (unsigned int v = 0; same && v < v1.n_vertices(); ++v)
      same = v1.get_vertices()[v] == v22.get_vertices()[v];
    for (auto c1 = v1.begin_active(), c2 = v22.begin_active(); same && c1 != v1.end(); ++c1, ++c2)
      for (unsigned int a = 0; a < 4; ++a)
        same = same && c1->vertex_index(a) == c2->vertex_index(a);
    tests::check("liver: Gmsh 1 and Gmsh 2.2 give the same triangulation", same);
  }

  // SOFA's vertex ids count the file's nodes from 0: the first node of sofa_torus_low_res.msh
  // (tag 1) is vertex 0 and its coordinates are on line 3.
  {
    dealii::Triangulation<3> triangulation;
    const auto numbering = fem::read_mesh(meshes + "sofa_torus_low_res.msh", triangulation);
    const auto &first    = triangulation.get_vertices()[numbering.vertex_of_file_vertex[0]];
    tests::check("SOFA torus: file vertex 0 is (1.48128, 0.293893, -0.338526)",
                 (first - dealii::Point<3>(1.481276839673519, 0.2938930094242096, -0.3385259009401004)).norm() < 1e-15);
  }

  tests::write_file("two_tetrahedra_v41.msh",
                    "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
                    "$Entities\n0 0 0 1\n1 0 0 0 1 1 1 0 0\n$EndEntities\n"
                    "$Nodes\n1 6 1 6\n3 1 0 6\n1\n2\n3\n4\n5\n6\n"
                    "0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n5 5 5\n$EndNodes\n"
                    "$Elements\n2 3 1 3\n2 1 2 1\n1 1 2 3\n3 1 4 2\n2 1 2 3 4\n3 2 3 4 5\n$EndElements\n");
  describe("Gmsh 4.1 with a triangle and an unused node", "two_tetrahedra_v41.msh");

  tests::write_file("two_tetrahedra.vtu",
                    "<?xml version=\"1.0\"?>\n"
                    "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                    "<UnstructuredGrid><Piece NumberOfPoints=\"6\" NumberOfCells=\"3\">\n"
                    "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">" +
                      two_tetrahedra_points +
                      "</DataArray></Points>\n"
                      "<Cells><DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">0 1 2 3 1 2 3 4 0 1 2</DataArray>\n"
                      "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">4 8 11</DataArray>\n"
                      "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10 10 5</DataArray></Cells>\n"
                      "</Piece></UnstructuredGrid></VTKFile>\n");
  describe("VTU with a triangle and an unused point", "two_tetrahedra.vtu");

  tests::write_file("two_tetrahedra.vtk", "# vtk DataFile Version 3.0\ntwo tetrahedra\nASCII\n"
                                          "DATASET UNSTRUCTURED_GRID\nPOINTS 6 double\n" +
                                            two_tetrahedra_points +
                                            "\nCELLS 3 13\n4 0 1 2 3\n4 1 2 3 4\n3 0 1 2\n"
                                            "CELL_TYPES 3\n10\n10\n5\n");
  describe("legacy VTK with a triangle and an unused point", "two_tetrahedra.vtk");

  // Every tetrahedron negatively oriented: another convention, reoriented as a whole.
  tests::write_file("negative_convention.msh", "$NOD\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
                                               "5 1 1 1\n$ENDNOD\n$ELM\n2\n"
                                               "1 4 1 1 4 1 3 2 4\n2 4 1 1 4 2 4 3 5\n$ENDELM\n");
  describe("Gmsh 1, all tetrahedra negatively oriented", "negative_convention.msh");
}
