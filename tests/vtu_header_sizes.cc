// The sizes in a VTU file's XML header are checked before VTK reads it (fem::read_vtk):
// VTK reserves what NumberOfPoints, NumberOfCells, NumberOfComponents and NumberOfTuples
// announce, so a broken number there (the fuzz_vtu finding: NumberOfComponents =
// "32147483647binary", on which VTK spun past the fuzzer's timeout) is one line naming the
// file and the line, and a header that announces more values than the file can hold, even
// inflated by zlib, too. Valid files, with either kind of quotes, still read.

#include "simulation_tests.h"

#include <warpchol/mesh/mesh_readers.h>

using namespace warpchol;

namespace
{
  /** A VTU file of two tetrahedra, with @p piece and @p points_array as its tags. */
  std::string vtu(const std::string &piece, const std::string &points_array)
  {
    return "<?xml version=\"1.0\"?>\n"
           "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
           "<UnstructuredGrid>\n" +
           piece + "\n<Points>\n" + points_array +
           "0 0 0  1 0 0  0 1 0  0 0 1  1 1 1</DataArray></Points>\n"
           "<Cells><DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">0 1 2 3 1 2 3 4</DataArray>\n"
           "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">4 8</DataArray>\n"
           "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10 10</DataArray></Cells>\n"
           "</Piece></UnstructuredGrid></VTKFile>\n";
  }

  const std::string piece  = "<Piece NumberOfPoints=\"5\" NumberOfCells=\"2\">";
  const std::string points = "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">";

  void read(const std::string &label, const std::string &filename, const std::string &text)
  {
    tests::write_file(filename, text);
    try
      {
        const fem::TetrahedralMesh mesh = fem::read_vtk(filename);
        std::cout << label << ": " << mesh.vertices.size() << " points, " << mesh.tetrahedra.size()
                  << " tetrahedra" << std::endl;
      }
    catch (const Error &error)
      {
        std::cout << label << ": " << error.what() << std::endl;
      }
  }
} // namespace

int main()
{
  read("valid", "valid.vtu", vtu(piece, points));
  read("valid, single quotes and spaces", "quotes.vtu",
       vtu("<Piece NumberOfPoints = ' 5 ' NumberOfCells='2'>",
           "<DataArray type='Float64' NumberOfComponents='3' format='ascii'>"));
  read("the fuzz finding: 32147483647binary components", "fuzz.vtu",
       vtu(piece, "<DataArray type=\"Float32\" NumberOfComponents=\"32147483647binary\" format=\"ascii\">"));
  read("negative points", "negative.vtu", vtu("<Piece NumberOfPoints=\"-5\" NumberOfCells=\"2\">", points));
  read("a count beyond 64 bits", "huge_count.vtu",
       vtu("<Piece NumberOfPoints=\"99999999999999999999999\" NumberOfCells=\"2\">", points));
  read("1e12 points", "huge_points.vtu", vtu("<Piece NumberOfPoints=\"1000000000000\" NumberOfCells=\"2\">", points));
  read("1e9 cells", "huge_cells.vtu", vtu("<Piece NumberOfPoints=\"5\" NumberOfCells=\"1000000000\">", points));
  read("2^31 components", "huge_components.vtu",
       vtu(piece, "<DataArray type=\"Float64\" NumberOfComponents=\"2147483647\" format=\"ascii\">"));
  read("1e10 tuples", "huge_tuples.vtu",
       vtu(piece, "<DataArray type=\"Float64\" NumberOfComponents=\"3\" NumberOfTuples=\"10000000000\" "
                  "format=\"ascii\">"));
}
