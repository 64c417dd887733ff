// What a run leaves on disk: the CSV log (header, one row per step), the VTU files every
// N steps with their fields and the PVD series listing them, and nothing else (no
// temporary file); when a step fails, what the steps before it wrote. And
// --print-parameters writes documented defaults that read back.

#include "simulation_tests.h"

#include <warpchol/app/simulation.h>

#include <algorithm>
#include <filesystem>
#include <regex>
#include <sstream>

using namespace warpchol;

namespace
{
  int run(const std::vector<std::string> &arguments, std::string *error_message = nullptr)
  {
    std::vector<const char *> argv{"warpchol"};
    for (const auto &argument : arguments)
      argv.push_back(argument.c_str());
    std::ostringstream out, err;
    const int          status = app::main(argv.size(), argv.data(), out, err);
    if (error_message)
      *error_message = err.str();
    else if (status != 0)
      std::cout << "exit " << status << ": " << err.str();
    return status;
  }

} // namespace

int main()
{
  tests::write_file("scene.prm", "subsection Mesh\n  set Source = box\n  set Box subdivisions = 2, 1, 1\nend\n"
                                 "subsection Time stepping\n  set Number of steps = 4\nend\n"
                                 "subsection Fixed vertices\n  set Region = box\n"
                                 "  set Box lower corner = -1, -1, -1\n  set Box upper corner = 0, 1, 1\nend\n"
                                 "subsection Gravity\n  set Acceleration = 0, -9.81, 0\nend\n"
                                 "subsection Output\n  set Directory = results\n  set Scene = box_scene\n"
                                 "  set VTU interval = 2\n  set Write log = true\n  set Progress = off\nend\n");
  tests::check("warpchol scene.prm exits with 0", run({"scene.prm"}) == 0);

  const std::string directory = "results/box_scene/";
  std::istringstream log(tests::read_file(directory + "log.csv"));
  std::string        header, line;
  std::getline(log, header);
  std::cout << "log header: " << header << std::endl;
  unsigned int rows = 0, well_formed = 0;
  while (std::getline(log, line))
    {
      ++rows;
      well_formed += std::count(line.begin(), line.end(), ',') == std::count(header.begin(), header.end(), ',');
    }
  tests::check("log: 4 rows with a value per column", rows == 4 && well_formed == 4);

  const std::string pvd = tests::read_file(directory + "box_scene.pvd");
  for (const std::string name : {"box_scene-00000.vtu", "box_scene-00002.vtu", "box_scene-00004.vtu"})
    {
      const std::string vtu = tests::read_file(directory + name);
      bool fields = true;
      for (const std::string field : {"displacement", "velocity", "rerotated", "steps_since_rerotation", "error_estimate"})
        fields = fields && vtu.find("Name=\"" + field + "\"") != std::string::npos;
      tests::check(name + " is in the series and has every field",
                   pvd.find("file=\"" + name + "\"") != std::string::npos && fields);
    }
  unsigned int n_files = 0;
  for (const auto &entry : std::filesystem::directory_iterator(directory))
    {
      (void)entry;
      ++n_files;
    }
  tests::check("the folder holds the log, the series and 3 VTU files, nothing else", n_files == 5);

  // Stiffness warping under a violent pull diverges (the report's "explosion"): the energy
  // detector stops the run with status 1 at the step whose energy passed the limit, long
  // before the velocities overflow; the log keeps every step up to that one, the VTU series
  // every file written before it.
  tests::write_file("diverging.prm",
                    "subsection Mesh\n  set Source = torus\n  set Torus toroidal cells = 8\nend\n"
                    "subsection Time stepping\n  set Time step = 0.02\n  set Number of steps = 400\nend\n"
                    "subsection Model\n  set Type = stiffness_warping\nend\n"
                    "subsection Fixed vertices\n  set Region = box\n"
                    "  set Box lower corner = -1, -1, -1\n  set Box upper corner = -0.33, 1, 1\nend\n"
                    "subsection Tool\n  set Region = sphere\n  set Sphere center = 0.4, 0, 0\n"
                    "  set Sphere radius = 0.06\n  set Spring stiffness = 200\n"
                    "  set Velocity = 0, 3, -3\n  set Duration = 1\nend\n"
                    "subsection Output\n  set Directory = results\n  set Write log = true\n"
                    "  set VTU interval = 5\nend\n");
  std::string message;
  const int   status = run({"diverging.prm"}, &message);
  std::smatch step;
  const bool  named  = std::regex_search(
    message, step, std::regex(R"(step (\d+): the energy of stiffness_warping grew to .* J \(start 0 J, work of the external loads .* J\), over .*: the simulation diverged)"));
  tests::check("a diverging run exits with 1, naming the step, the model and the energies", status == 1 && named);
  std::istringstream partial_log(tests::read_file("results/diverging/log.csv"));
  unsigned int       logged_rows = 0;
  while (std::getline(partial_log, line))
    ++logged_rows;
  const unsigned int failing_step = named ? std::stoul(step[1].str()) : 0;
  tests::check("its log holds the header and every step up to the failing one",
               named && logged_rows == failing_step + 1);
  const std::string diverging_pvd = tests::read_file("results/diverging/diverging.pvd");
  unsigned int vtu_files = 0;
  for (auto at = diverging_pvd.find(".vtu"); at != std::string::npos; at = diverging_pvd.find(".vtu", at + 1))
    ++vtu_files;
  tests::check("its VTU series holds every file before the failing step", named && vtu_files == (failing_step - 1) / 5 + 1);

  // A new file only (an existing one is refused): the run before in this folder left one.
  std::filesystem::remove("defaults.prm");
  tests::check("--print-parameters defaults.prm exits with 0", run({"--print-parameters", "defaults.prm"}) == 0);
  std::ostringstream printed;
  app::AllParameters::print_defaults(printed);
  tests::check("the file holds the documented defaults", tests::read_file("defaults.prm") == printed.str() &&
                                                            printed.str().find("# ") != std::string::npos);
  tests::expect_error("the defaults read back", [] {
    const app::AllParameters parameters("defaults.prm");
    if (parameters.model.type == fem::ModelType::warp_canceling && parameters.solver.settings.method ==
                                                       cholesky::FactorizationMethod::supernodal)
      throw Error("(read back, no error)");
  });
}
