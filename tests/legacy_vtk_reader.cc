// Our parser of legacy VTK files (fem::read_legacy_vtk, which replaced VTK's
// vtkUnstructuredGridReader): ASCII version 3, BINARY (big-endian), version 5.1's OFFSETS
// and CONNECTIVITY, FIELD data and METADATA skipped, lower-case keywords; and one line
// naming the file and the line (or section) for a truncated file, counts that the file
// cannot hold, point ids out of range, other volume cells, and the fuzz_vtk finding that
// crashed VTK's reader.

#include "simulation_tests.h"

#include <warpchol/mesh/mesh_readers.h>

#include <cstdint>
#include <cstring>

using namespace warpchol;

namespace
{
  void describe(const std::string &label, const std::string &filename)
  {
    try
      {
        const fem::TetrahedralMesh mesh = fem::read_legacy_vtk(filename);
        std::cout << label << ": " << mesh.vertices.size() << " points, " << mesh.tetrahedra.size()
                  << " tetrahedra, last point (" << mesh.vertices.back()[0] << " " << mesh.vertices.back()[1] << " "
                  << mesh.vertices.back()[2] << "), last tetrahedron";
        for (const unsigned int v : mesh.tetrahedra.back())
          std::cout << " " << v;
        std::cout << " (" << mesh.locations.back() << ")" << std::endl;
      }
    catch (const Error &error)
      {
        std::cout << label << ": " << error.what() << std::endl;
      }
  }

  void write_and_describe(const std::string &label, const std::string &filename, const std::string &text)
  {
    tests::write_file(filename, text);
    describe(label, filename);
  }

  /** Big-endian bytes of a value. */
  template <typename T>
  std::string big_endian(const T value)
  {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    std::string result(bytes, sizeof(T));
    return std::string(result.rbegin(), result.rend()); // the test machines are little-endian
  }

  const std::string header = "# vtk DataFile Version 3.0\ntwo tetrahedra\nASCII\nDATASET UNSTRUCTURED_GRID\n";
  const std::string points = "POINTS 6 float\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n5 5 5\n";
  const std::string cells  = "CELLS 3 14\n4 0 1 2 3\n4 1 4 2 3\n3 0 1 2\nCELL_TYPES 3\n10\n10\n5\n";

  std::string binary_file(const std::string &field)
  {
    std::string text = "# vtk DataFile Version 3.0\nbinary\nBINARY\nDATASET UNSTRUCTURED_GRID\n" + field +
                       "POINTS 6 double\n";
    const double coordinates[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1, 5, 5, 5};
    for (const double c : coordinates)
      text += big_endian(c);
    text += "\nCELLS 3 14\n";
    const std::int32_t lists[] = {4, 0, 1, 2, 3, 4, 1, 4, 2, 3, 3, 0, 1, 2};
    for (const std::int32_t i : lists)
      text += big_endian(i);
    text += "\nCELL_TYPES 3\n";
    for (const std::int32_t type : {10, 10, 5})
      text += big_endian(type);
    return text + "\nCELL_DATA 3\nSCALARS id int 1\nLOOKUP_TABLE default\n";
  }

  std::string version51(const std::string &offsets_type, const std::string &offsets,
                        const std::string &connectivity)
  {
    return "# vtk DataFile Version 5.1\nvtk output\nASCII\nDATASET UNSTRUCTURED_GRID\n"
           "POINTS 6 double\n0 0 0 1 0 0 0 1 0 0 0 1 1 1 1 5 5 5\n"
           "METADATA\nINFORMATION 0\n\n"
           "CELLS 3 8\nOFFSETS " +
           offsets_type + "\n" + offsets + "\nCONNECTIVITY vtktypeint64\n" + connectivity +
           "\nCELL_TYPES 2\n10\n10\n";
  }
} // namespace

int main()
{
  std::cout << "-- files that read" << std::endl;
  write_and_describe("ASCII version 3 with a triangle and point data", "ascii.vtk",
                     header + points + cells + "POINT_DATA 6\nSCALARS id int 1\nLOOKUP_TABLE default\n0 1 2 3 4 5\n");
  write_and_describe("lower-case keywords, CRLF lines", "lower_case.vtk",
                     "# vtk DataFile Version 3.0\r\nlower\r\nascii\r\ndataset unstructured_grid\r\n"
                     "points 5 double\r\n0 0 0 1 0 0 0 1 0 0 0 1 1 1 1\r\ncells 2 10\r\n4 0 1 2 3\r\n"
                     "4 1 4 2 3\r\ncell_types 2\r\n10 10\r\n");
  write_and_describe("BINARY", "binary.vtk", binary_file(""));
  {
    std::string field = "FIELD FieldData 2\nTIME 1 1 double\n" + big_endian(2.5) + "\nflags 2 3 int\n";
    for (std::int32_t i = 0; i < 6; ++i)
      field += big_endian(i);
    write_and_describe("BINARY with FIELD data before POINTS", "binary_field.vtk", binary_file(field + "\n"));
  }
  write_and_describe("version 5.1 OFFSETS and CONNECTIVITY, METADATA", "v51.vtk",
                     version51("vtktypeint64", "0 4 8", "0 1 2 3 1 4 2 3"));
  {
    std::string text = "# vtk DataFile Version 5.1\nvtk output\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 5 float\n";
    for (const float c : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 1.f, 1.f, 1.f})
      text += big_endian(c);
    text += "\nCELLS 3 8\nOFFSETS vtktypeint32\n";
    for (const std::int32_t o : {0, 4, 8})
      text += big_endian(o);
    text += "\nCONNECTIVITY vtktypeint64\n";
    for (const std::int64_t i : {0, 1, 2, 3, 1, 4, 2, 3})
      text += big_endian(i);
    text += "\nCELL_TYPES 2\n" + big_endian(std::int32_t(10)) + big_endian(std::int32_t(10)) + "\n";
    write_and_describe("version 5.1 BINARY, 32-bit offsets", "v51_binary.vtk", text);
  }
  write_and_describe("FIELD data before POINTS (ASCII, with a string array and a NULL_ARRAY)", "field.vtk",
                     header + "FIELD FieldData 3\nTIME 1 1 double\n2.5\nNULL_ARRAY\nnames 1 2 string\n"
                              "first name\nsecond\n" +
                       points + cells);

  std::cout << "-- files refused" << std::endl;
  write_and_describe("truncated in POINTS", "truncated.vtk", header + "POINTS 6 float\n0 0 0\n1 0 0\n0 1");
  write_and_describe("truncated in its last coordinates", "truncated_end.vtk", header + "POINTS 2 float\n0 0 0\n1 0 \n");
  {
    const std::string text = binary_file("");
    write_and_describe("BINARY truncated in CELLS", "truncated_binary.vtk", text.substr(0, text.find("CELLS") + 40));
  }
  write_and_describe("truncated before CELL_TYPES", "no_cell_types.vtk", header + points + "CELLS 3 14\n4 0 1 2 3\n4 1 4 2 3\n3 0 1 2\n");
  write_and_describe("a header claiming 1e12 points", "huge_points.vtk", header + "POINTS 1000000000000 float\n0 0 0\n");
  write_and_describe("a count beyond 64 bits", "huge_count.vtk", header + "POINTS 99999999999999999999999 float\n0 0 0\n");
  write_and_describe("1e12 cells", "huge_cells.vtk", header + points + "CELLS 1000000000000 5000000000000\n4 0 1 2 3\n");
  write_and_describe("BINARY 1e12 points", "huge_binary.vtk",
                     "# vtk DataFile Version 3.0\nb\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 1000000000000 double\n" +
                       std::string(48, '\0'));
  write_and_describe("BINARY 1e6 points in 48 bytes", "many_binary.vtk",
                     "# vtk DataFile Version 3.0\nb\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 1000000 double\n" +
                       std::string(48, '\0'));
  write_and_describe("version 5.1 with 1e12 offsets", "huge_offsets.vtk",
                     "# vtk DataFile Version 5.1\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n" + points +
                       "CELLS 1000000000000 8\nOFFSETS vtktypeint64\n0 4 8\n");
  write_and_describe("a point id out of range", "id_out_of_range.vtk",
                     header + points + "CELLS 2 10\n4 0 1 2 3\n4 1 4 2 6\nCELL_TYPES 2\n10 10\n");
  write_and_describe("a negative point id in a triangle", "negative_id.vtk",
                     header + points + "CELLS 2 9\n4 0 1 2 3\n3 0 -1 2\nCELL_TYPES 2\n10 5\n");
  write_and_describe("version 5.1 id out of range", "v51_out_of_range.vtk",
                     version51("vtktypeint64", "0 4 8", "0 9 2 3 1 4 2 3"));
  write_and_describe("version 5.1 offsets past the connectivity", "v51_bad_offsets.vtk",
                     version51("vtktypeint64", "0 4 9", "0 1 2 3 1 4 2 3"));
  write_and_describe("version 5.1 decreasing offsets", "v51_decreasing.vtk",
                     version51("vtktypeint64", "0 5 4", "0 1 2 3 1 4 2 3"));
  write_and_describe("version 5.1 floating-point offsets", "v51_float_offsets.vtk",
                     version51("float", "0 4 8", "0 1 2 3 1 4 2 3"));
  write_and_describe("a cell list longer than CELLS says", "long_list.vtk",
                     header + points + "CELLS 2 9\n4 0 1 2 3\n5 1 4 2 3 0\nCELL_TYPES 2\n10 10\n");
  write_and_describe("CELLS with more integers than the lists", "extra_integers.vtk",
                     header + points + "CELLS 1 6\n4 0 1 2 3 7\nCELL_TYPES 1\n10\n");
  write_and_describe("fewer cell types than cells", "few_types.vtk", header + points + "CELLS 3 14\n4 0 1 2 3\n4 1 4 2 3\n3 0 1 2\nCELL_TYPES 2\n10 10\n");
  write_and_describe("a hexahedron", "hexahedron.vtk",
                     header + points + "CELLS 2 14\n4 0 1 2 3\n8 0 1 2 3 4 5 0 1\nCELL_TYPES 2\n10 12\n");
  write_and_describe("a tetrahedron with 3 points", "three_point_tetrahedron.vtk",
                     header + points + "CELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n10\n");
  write_and_describe("triangles only", "triangles.vtk", header + points + "CELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n5\n");
  write_and_describe("a coordinate that is not a number", "nan.vtk", header + "POINTS 1 float\n0 nan 0\n");
  write_and_describe("POLYDATA", "polydata.vtk",
                     "# vtk DataFile Version 3.0\nsurface\nASCII\nDATASET POLYDATA\nPOINTS 3 double\n0 0 0 1 0 0 0 1 0\n");
  write_and_describe("neither ASCII nor BINARY", "no_format.vtk",
                     "# vtk DataFile Version 3.0\ntitle\nTEXT\nDATASET UNSTRUCTURED_GRID\n");
  write_and_describe("an unknown keyword", "unknown_keyword.vtk", header + points + "VERTICES 1 2\n1 0\n");
  write_and_describe("an unknown data type", "unknown_type.vtk", header + "POINTS 1 quaternion\n0 0 0\n");
  write_and_describe("a FIELD with 1e12 tuples", "huge_field.vtk", header + "FIELD f 1\na 3 1000000000000 double\n1 2 3\n");
  write_and_describe("two POINTS sections", "two_points.vtk", header + points + points + cells);
  write_and_describe("BINARY data on the keyword line", "binary_same_line.vtk",
                     "# vtk DataFile Version 3.0\nb\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 1 float \x01\x02\n");
  // Copied here: the message names the file as it is given.
  write_and_describe("fuzz_vtk's finding (VTK's segmentation fault in ReadMeshSimple)", "fuzz_finding.vtk",
                     tests::read_file(std::string(SOURCE_DIR) +
                                      "/../fuzz/regressions/vtk/vtk_segv_read_mesh_simple_field_in_points.vtk"));
  write_and_describe("fuzz_vtk (our parser): BINARY cell lists that end before the cells", "fuzz_binary_cells.vtk",
                     tests::read_file(std::string(SOURCE_DIR) + "/../fuzz/regressions/vtk/binary_cells_end_before_n.vtk"));
}
