// A path in a parameter file is taken relative to the folder of the file it is written in,
// an included file's as the top file's: "include FILE" itself, and Mesh/File. A scene of
// another folder, with its mesh beside it, can be included from anywhere (it failed with
// "../meshes/...: cannot open the mesh file", resolved against the top file's folder). An
// error in an included file names that file and its line.

#include "simulation_tests.h"

#include <filesystem>

namespace
{
  const std::string two_tetrahedra = "$NOD\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n$ENDNOD\n"
                                     "$ELM\n2\n1 4 1 1 4 1 2 3 4\n2 4 1 1 4 2 3 4 5\n$ENDELM\n";

  /** Read @p file; print its mesh file and the number of tets, or the error. */
  void read(const std::string &label, const std::string &file)
  {
    tests::print_result_or_error(label, [&] {
      const warpchol::app::AllParameters parameters(file);
      const warpchol::app::Scene         scene(parameters);
      return "mesh " + parameters.mesh_file_path() + ", " + std::to_string(scene.body().n_elements()) +
             " tets, density " + warpchol::format_number(parameters.material.density);
    });
  }
} // namespace

int main()
{
  // library/scenes/pull.prm uses library/meshes/two.msh; mine/ holds the user's files.
  std::filesystem::create_directories("library/meshes");
  std::filesystem::create_directories("library/scenes/parts");
  std::filesystem::create_directories("mine");
  tests::write_file("library/meshes/two.msh", two_tetrahedra);
  tests::write_file("library/scenes/pull.prm", "subsection Mesh\n  set Source = file\n"
                                               "  set File = ../meshes/two.msh\nend\n");
  tests::write_file("library/scenes/heavy_pull.prm", "include parts/material.prm\ninclude pull.prm\n");
  tests::write_file("library/scenes/parts/material.prm", "subsection Material\n  set Density = 3\nend\n");

  tests::write_file("mine/relative.prm", "include ../library/scenes/pull.prm\n");
  read("include by a relative path", "mine/relative.prm");
  tests::write_file("mine/absolute.prm", "include " + std::filesystem::absolute("library/scenes/pull.prm").string() + "\n");
  tests::print_result_or_error("include by an absolute path", [] {
    const std::string mesh = warpchol::app::AllParameters("mine/absolute.prm").mesh_file_path();
    const std::string end  = "/library/scenes/../meshes/two.msh";
    return mesh.size() > end.size() && mesh.compare(mesh.size() - end.size(), end.size(), end) == 0 ?
             std::string("the mesh in the included file's folder") :
             "the mesh at " + mesh;
  });
  tests::write_file("mine/nested.prm", "include ../library/scenes/heavy_pull.prm\n");
  read("an included file that includes others", "mine/nested.prm");
  tests::write_file("mine/two.msh", two_tetrahedra);
  tests::write_file("mine/own_mesh.prm", "include ../library/scenes/pull.prm\n"
                                         "subsection Mesh\n  set File = two.msh\nend\n");
  read("the mesh set again after the include", "mine/own_mesh.prm");
  tests::write_file("mine/in_subsection.prm", "subsection Material\n  include ../library/scenes/density.prm\nend\n");
  tests::write_file("library/scenes/density.prm", "set Density = 4\n");
  tests::print_result_or_error("an include inside a subsection", [] {
    return warpchol::format_number(warpchol::app::AllParameters("mine/in_subsection.prm").material.density);
  });

  std::cout << "-- errors in included files" << std::endl;
  // Per case: the file in library/scenes/ (if any) and mine/NAME.prm, which includes it.
  const struct
  {
    const char *label, *name, *included, *including;
  } errors[] = {
    {"a value out of range", "bad_value", "subsection Material\n  set Poisson's ratio = 0.5\nend\n",
     "# comment\ninclude ../library/scenes/bad_value.prm\n"},
    {"an unknown entry", "unknown", "subsection Material\n\n  set Stiffness = 3\nend\n",
     "subsection Gravity\nend\ninclude ../library/scenes/unknown.prm\n"},
    {"a subsection left open", "unclosed", "subsection Material\n  set Density = 3\n",
     "include ../library/scenes/unclosed.prm\nend\n"},
    {"a file of the working directory's, not of this folder", "missing", nullptr, "include pull.prm\n"}};
  for (const auto &error : errors)
    {
      if (error.included)
        tests::write_file("library/scenes/" + std::string(error.name) + ".prm", error.included);
      tests::write_file("mine/" + std::string(error.name) + ".prm", error.including);
      read(error.label, "mine/" + std::string(error.name) + ".prm");
    }
}
