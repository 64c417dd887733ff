// A mesh file's format is told by its first non-blank bytes, its extension only when they
// say nothing: SOFA's Bunny.vtk holds VTK XML (a .vtu UnstructuredGrid) under a .vtk name
// (tests/data/xml_content.vtk is such a file), and reads as the XML it is; so do a legacy
// VTK file named .vtu and a Gmsh file named .vtk. A file that neither its content nor its
// extension places is refused with one line quoting its start.

#include "simulation_tests.h"

#include <warpchol/mesh/mesh_readers.h>

using namespace warpchol;

namespace
{
  std::string name_of(const fem::MeshFormat format)
  {
    switch (format)
      {
        case fem::MeshFormat::gmsh:
          return "Gmsh";
        case fem::MeshFormat::legacy_vtk:
          return "legacy VTK";
        case fem::MeshFormat::vtk_xml:
          return "VTK XML";
        default:
          return "unknown";
      }
  }

  void describe(const std::string &label, const std::string &filename)
  {
    std::cout << label << ": detected " << name_of(fem::detect_mesh_format(filename)) << ", ";
    try
      {
        dealii::Triangulation<3> triangulation;
        const auto               numbering = fem::read_mesh(filename, triangulation);
        long                     dropped   = 0;
        for (const long v : numbering.vertex_of_file_vertex)
          dropped += v < 0;
        std::cout << triangulation.n_vertices() << " vertices, " << triangulation.n_active_cells()
                  << " tets, " << dropped << " unused vertices dropped" << std::endl;
      }
    catch (const Error &error)
      {
        std::cout << error.what() << std::endl;
      }
  }

  const std::string points = "0 0 0  1 0 0  0 1 0  0 0 1  1 1 1  5 5 5";
} // namespace

int main()
{
  describe("VTK XML named .vtk (tests/data)", tests::data_file("xml_content.vtk"));

  tests::write_file("legacy_named.vtu", "# vtk DataFile Version 3.0\ntwo tetrahedra\nASCII\n"
                                        "DATASET UNSTRUCTURED_GRID\nPOINTS 6 double\n" +
                                          points +
                                          "\nCELLS 3 13\n4 0 1 2 3\n4 1 2 3 4\n3 0 1 2\n"
                                          "CELL_TYPES 3\n10\n10\n5\n");
  describe("legacy VTK named .vtu", "legacy_named.vtu");

  tests::write_file("gmsh_named.vtk", "$NOD\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n$ENDNOD\n"
                                      "$ELM\n2\n1 4 1 1 4 1 2 3 4\n2 4 1 1 4 2 3 4 5\n$ENDELM\n");
  describe("Gmsh 1 named .vtk", "gmsh_named.vtk");

  // Without a recognisable start the extension decides: the Gmsh reader's own message.
  tests::write_file("no_header.msh", "5\n1 0 0 0\n");
  describe("a .msh without $MeshFormat", "no_header.msh");

  tests::write_file("surface.off", "OFF\n4 4 6\n");
  describe("OFF", "surface.off");
}
