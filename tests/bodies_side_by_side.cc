// A scene of several bodies runs each body as the scene of one would: three copies of the
// small torus (linear, WCC at threshold 0.3, corotational) end where the same scenes run
// alone end, to rounding. The one VTU series holds the three bodies (three times the cells,
// a "body" cell field), each body has its own log, and the summary names each body.

#include "simulation_tests.h"

#include <warpchol/app/simulation.h>

#include <fstream>
#include <regex>
#include <sstream>

namespace
{
  const std::string output = "subsection Output\n  set Print timings = false\n  set Progress = off\n"
                             "  set Directory = results\n  set VTU interval = 5\n  set Write log = true\nend\n";

  std::string scene(const std::string &extra)
  {
    std::string text = tests::small_torus_scene("  set Type = warp_canceling\n  set Rerotation threshold = 0.3\n");
    return text + "subsection Time stepping\n  set Number of steps = 10\nend\n" + output + extra;
  }

} // namespace

int main()
{
  tests::write_file("three.prm",
                    scene("subsection Bodies\n  set Number of bodies = 3\n  set Spacing = 1, 0, 0\n"
                          "  set Models = linear, warp_canceling, corotational\nend\n"));
  warpchol::app::Simulation three{warpchol::app::AllParameters("three.prm")};
  std::ostringstream        summary;
  three.run(summary);
  std::cout << summary.str();

  const std::vector<std::string> models{"linear", "warp_canceling", "corotational"};
  for (unsigned int i = 0; i < 3; ++i)
    {
      const auto alone = tests::run_scene("alone.prm", scene("subsection Model\n  set Type = " + models[i] + "\nend\n"), 10);
      tests::check_below("body " + std::to_string(i + 1) + " against the scene alone",
                         tests::relative_difference(three.scene(i).integrator().positions(), alone,
                                                    three.scene(i).body().rest_positions()),
                         1e-12);
    }

  const std::string vtu = tests::read_file(three.output_directory() + "/three-00010.vtu");
  std::smatch       cells;
  tests::check("the VTU file holds the cells of the three bodies",
               std::regex_search(vtu, cells, std::regex("NumberOfCells=\"([0-9]+)\"")) &&
                 std::stoul(cells[1]) == 3 * three.scene(0).body().n_elements());
  tests::check("and a cell field body", vtu.find("Name=\"body\"") != std::string::npos);
  tests::check("a log per body", std::ifstream(three.output_directory() + "/log_body3.csv").good() &&
                                   !std::ifstream(three.output_directory() + "/log.csv").good());
}
