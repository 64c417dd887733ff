// "warpchol --print-parameters FILE" writes a new file only: an existing FILE (it replaced
// a scene once) is refused in one line with exit status 2 and left as it was; without FILE
// the defaults go to standard output.

#include "simulation_tests.h"

#include <filesystem>

int main()
{
  const std::string scene = "subsection Material\n  set Density = 3\nend\n";
  tests::write_file("scene.prm", scene);
  std::cout << "existing file: " << tests::run_warpchol({"--print-parameters", "scene.prm"}) << std::endl;
  tests::check("the existing file is left as it was", tests::read_file("scene.prm") == scene);

  std::filesystem::remove("defaults.prm");
  std::cout << "new file: " << tests::run_warpchol({"--print-parameters", "defaults.prm"}) << std::endl;
  tests::check("the new file holds the defaults, which read back",
               tests::read_file("defaults.prm").find("subsection Material") != std::string::npos &&
                 warpchol::app::AllParameters("defaults.prm").material.density == 20);
  std::cout << "the same file again: " << tests::run_warpchol({"--print-parameters", "defaults.prm"})
            << std::endl;

  std::filesystem::create_directories("a_directory");
  std::cout << "a directory: " << tests::run_warpchol({"--print-parameters", "a_directory"}) << std::endl;

  const char        *argv[] = {"warpchol", "--print-parameters"};
  std::ostringstream out, err;
  const int          status = warpchol::app::main(2, argv, out, err);
  tests::check("no file: the defaults on standard output, exit 0",
               status == 0 && err.str().empty() && out.str().find("subsection Material") != std::string::npos);
}
