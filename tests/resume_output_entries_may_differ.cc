// --resume takes a checkpoint written with other output entries (those that change no step:
// VTU interval and precision, Print timings, Progress, Checkpoint interval) and ends, to the
// bit, where the run never stopped ends; the VTU series lists the files written before and
// goes on at the new interval, or stops with VTU interval = 0. The log, whose rows the
// checkpoint holds, must stay as it was.

#include "simulation_tests.h"

#include <cstring>
#include <filesystem>

namespace
{
  std::string scene(const unsigned int n_steps, const std::string &directory, const std::string &output)
  {
    return tests::small_torus_scene("  set Type = warp_canceling\n  set Rerotation threshold = 0.3\n") +
           "subsection Time stepping\n  set Number of steps = " + std::to_string(n_steps) + "\nend\n"
           "subsection Output\n  set Directory = " + directory + "\n  set Write log = true\n"
           "  set Checkpoint interval = 10\n" + output + "end\n";
  }

  const std::string written_with = "  set VTU interval = 10\n  set Print timings = false\n  set Progress = off\n";

  /** Run @p file (resumed if @p resume); its positions at the end, or none if refused. */
  std::vector<warpchol::fem::Vector3> run(const std::string &label, const std::string &file, const bool resume)
  {
    std::vector<warpchol::fem::Vector3> positions;
    tests::print_result_or_error(label, [&] {
      warpchol::app::Simulation simulation{warpchol::app::AllParameters(file)};
      if (resume)
        simulation.resume();
      std::ostringstream summary;
      simulation.run(summary);
      positions = simulation.scene(0).integrator().positions();
      return "ran to step " + std::to_string(simulation.totals(0).steps);
    });
    return positions;
  }

  /** The VTU files of results/resumed/resumed.pvd, by step. */
  std::string pvd_steps()
  {
    const std::string pvd = tests::read_file("results/resumed/resumed.pvd");
    std::string       steps;
    for (auto at = pvd.find("resumed-"); at != std::string::npos; at = pvd.find("resumed-", at + 1))
      steps += " " + pvd.substr(at + 8, 5);
    return steps;
  }
} // namespace

int main()
{
  std::filesystem::remove_all("results");
  tests::write_file("resumed.prm", scene(20, "results", written_with));
  run("written with VTU interval 10, float32", "resumed.prm", false);

  tests::write_file("resumed.prm", scene(30, "results",
                                         "  set VTU interval = 5\n  set VTU precision = float64\n"
                                         "  set Print timings = true\n  set Progress = auto\n"
                                         "  set Checkpoint interval = 3\n"));
  const auto resumed = run("resumed with VTU interval 5, float64, timings, progress auto, checkpoints every 3", "resumed.prm", true);
  std::cout << "  the series lists the steps" << pvd_steps() << std::endl;
  tests::check("  the files after the checkpoint are float64",
               tests::read_file("results/resumed/resumed-00025.vtu").find("Float64") != std::string::npos);

  tests::write_file("whole.prm", scene(30, "whole", written_with));
  const auto whole = run("the same run, never stopped", "whole.prm", false);
  tests::check("  positions identical to the bit",
               resumed.size() == whole.size() &&
                 std::memcmp(resumed.data(), whole.data(), whole.size() * sizeof(whole[0])) == 0);

  tests::write_file("resumed.prm", scene(35, "results", "  set VTU interval = 0\n"));
  run("resumed again with VTU interval 0", "resumed.prm", true);
  std::cout << "  the series still lists the steps" << pvd_steps() << std::endl;

  tests::write_file("resumed.prm", scene(40, "results", "  set Write log = false\n"));
  run("resumed without the log", "resumed.prm", true);
}
