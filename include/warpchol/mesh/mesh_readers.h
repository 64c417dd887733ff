#pragma once

#include <deal.II/grid/tria.h>

#include <array>
#include <string>
#include <vector>

/**
 * @file
 * Tetrahedral meshes from files: Gmsh ASCII .msh (versions 1, 2.2 and 4.1), legacy VTK
 * .vtk and VTK XML .vtu. The format is recognised by the file's first bytes, and by its
 * extension only when they say nothing: SOFA's Bunny.vtk holds VTK XML.
 *
 * Every format is first read into a TetrahedralMesh (Gmsh by a line-aware scanner that
 * keeps the tetrahedra and skips lines, triangles and points; legacy VTK files by our own
 * parser; VTK XML files through the VTK library, as ParaView reads them), checked (each
 * element's orientation and volume, no element twice, with the file and line or cell that
 * is wrong), stripped of the vertices no tetrahedron uses, and then handed to deal.II's
 * GridIn as a Gmsh stream of tetrahedra only.
 */
namespace warpchol::fem
{
  /** A tetrahedral mesh as a file describes it. */
  struct TetrahedralMesh
  {
    /** Vertex coordinates, in the file's order. */
    std::vector<std::array<double, 3>> vertices;
    /** The 4 vertices (indices into @p vertices) of every tetrahedron, in the file's order. */
    std::vector<std::array<unsigned int, 4>> tetrahedra;
    /** Where each tetrahedron comes from, for messages ("mesh.msh:812", "cell 17 of mesh.vtu"). */
    std::vector<std::string> locations;
    /** The file name, for messages. */
    std::string name;
  };

  /**
   * What read_mesh() did with the file's vertices: @p vertex_of_file_vertex[i] is the
   * triangulation vertex of the i-th vertex of the file (0-based, in the order the file
   * lists them, which is SOFA's numbering), or -1 if no tetrahedron uses it (dropped).
   */
  struct MeshFileNumbering
  {
    std::vector<long> vertex_of_file_vertex;
  };

  /** The mesh formats that read_mesh() knows. */
  enum class MeshFormat
  {
    gmsh,
    legacy_vtk,
    vtk_xml,
    unknown
  };

  /**
   * The format of @p filename by its first non-blank bytes: "$MeshFormat" or "$NOD" is
   * Gmsh, "# vtk DataFile" legacy VTK, "<?xml" or "<VTKFile" VTK XML; unknown otherwise
   * (or if the file cannot be read).
   */
  MeshFormat detect_mesh_format(const std::string &filename);

  /** Scan a Gmsh ASCII file (version 1, 2.2 or 4.1). Throws InputError "FILE:LINE: ...". */
  TetrahedralMesh read_gmsh(const std::string &filename);

  /**
   * Read a legacy VTK (read_legacy_vtk()) or a VTK XML unstructured grid (through the VTK
   * library), the one or the other as detect_mesh_format() says (by the extension, .vtu
   * for XML, if it cannot tell).
   */
  TetrahedralMesh read_vtk(const std::string &filename);

  /**
   * Parse a legacy VTK unstructured grid (.vtk: ASCII or BINARY, the cell lists of
   * versions before 5 or the OFFSETS/CONNECTIVITY arrays of version 5.1; FIELD data and
   * METADATA skipped, POINT_DATA and CELL_DATA ignored) with our own parser, which checks
   * every count against the bytes left in the file before allocating and every point id.
   * Keeps the tetrahedra (VTK cell type 10), skips cells of dimension < 3, refuses other
   * volume cells. Throws InputError "FILE:LINE: ..." (ASCII) or naming the section (BINARY).
   */
  TetrahedralMesh read_legacy_vtk(const std::string &filename);

  /**
   * Check the elements of @p mesh: every tetrahedron must have a volume, no two the same
   * four vertices, and all the same orientation. A file whose tetrahedra are all negatively
   * oriented (the opposite convention) is accepted: its tetrahedra are reoriented. Throws
   * InputError naming the first degenerate or inverted element and its location, or both
   * cells of a tetrahedron listed twice.
   */
  void check_and_orient(TetrahedralMesh &mesh);

  /**
   * Fill @p triangulation (cleared first) with the tetrahedra of @p mesh, checked and
   * oriented, dropping the unused vertices, through GridIn (as a Gmsh 2.2 stream).
   */
  MeshFileNumbering create_triangulation(TetrahedralMesh mesh, dealii::Triangulation<3> &triangulation);

  /**
   * Read the mesh file @p filename, in the format detect_mesh_format() finds or, if it
   * finds none, that of its extension (.msh, .vtk, .vtu), into @p triangulation. Throws
   * InputError naming the file (and line) on any problem.
   */
  MeshFileNumbering read_mesh(const std::string &filename, dealii::Triangulation<3> &triangulation);
} // namespace warpchol::fem
