// A directory given where a file is read (a parameter file, a mesh, a matrix) is named as
// a directory, not read as an empty file ("unexpected end of file"); every reader checks
// through the same check_input_file(). (tools/warpchol-factor.directory checks the
// program's exit status.)

#include "simulation_tests.h"

#include <warpchol/app/simulation.h>
#include <warpchol/base/input_file.h>
#include <warpchol/mesh/mesh_readers.h>
#include <warpchol/sparse/matrix_market.h>

#include <filesystem>
#include <sstream>

using namespace warpchol;

namespace
{
  void run(const std::string &label, const std::vector<std::string> &arguments)
  {
    std::cout << label << ": " << tests::run_warpchol(arguments) << std::endl;
  }
} // namespace

int main()
{
  std::filesystem::create_directories("a_directory");
  std::filesystem::create_directories("mesh_directory.msh");
  std::filesystem::create_directories("scene_directory.prm");

  run("a directory as the parameter file", {"scene_directory.prm"});
  tests::write_file("mesh_is_directory.prm",
                    "subsection Mesh\n  set Source = file\n  set File = mesh_directory.msh\nend\n");
  run("a directory as the mesh", {"mesh_is_directory.prm"});
  tests::write_file("mesh_is_directory_vtk.prm",
                    "subsection Mesh\n  set Source = file\n  set File = a_directory\nend\n");
  run("a directory without extension as the mesh", {"mesh_is_directory_vtk.prm"});

  tests::expect_error("Gmsh reader", [] { fem::read_gmsh("mesh_directory.msh"); });
  tests::expect_error("VTK reader", [] { fem::read_vtk("a_directory"); });
  tests::expect_error("Matrix Market reader", [] { sparse::read_matrix_market("a_directory"); });
  tests::expect_error("a missing file", [] { check_input_file("no_such_file", "matrix file"); });
  tests::check("a regular file passes", [] {
    tests::write_file("regular.txt", "text\n");
    check_input_file("regular.txt", "text file");
    return true;
  }());
}
