// A run killed while it wrote a file leaves its temporary (SCENE-NNNNN.vtu.tmp.PID): the
// next run that opens that output folder, or a --resume, removes the temporaries of
// processes that no longer run, and leaves those of a process that runs (another writer's)
// and every other file.

#include "simulation_tests.h"

#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>

namespace
{
  /** The scene of @p steps steps, writing its log, VTU files and checkpoints to results/scene/. */
  std::string scene(const unsigned int steps)
  {
    return tests::small_torus_scene("  set Type = linear\n") +
           "subsection Time stepping\n  set Number of steps = " + std::to_string(steps) + "\nend\n"
           "subsection Output\n  set Directory = results\n  set Write log = true\n  set VTU interval = 1\n"
           "  set Checkpoint interval = 1\n  set Print timings = false\n  set Progress = off\nend\n";
  }
} // namespace

int main()
{
  // A process that has ended: its id names the killed run's temporaries. Forked first,
  // while this process has no thread.
  const pid_t ended = fork();
  if (ended == 0)
    _exit(0);
  waitpid(ended, nullptr, 0);
  // The parent, the test driver, runs: another writer.
  const std::string dead = std::to_string(ended), alive = std::to_string(getppid());

  std::filesystem::create_directories("results/scene");
  const std::vector<std::pair<std::string, std::string>> files = {
    {"scene-00040.vtu.tmp." + dead, "scene-00040.vtu.tmp.DEAD"},
    {"log.csv.tmp." + dead, "log.csv.tmp.DEAD"},
    {"threshold_sweep.csv.tmp." + alive, "threshold_sweep.csv.tmp.RUNNING"},
    {"notes.tmp.txt", "notes.tmp.txt"},
    {"data.tmp.12ab", "data.tmp.12ab"}};
  for (const auto &file : files)
    tests::write_file("results/scene/" + file.first, "half a file");
  const auto show = [&](const std::string &when) {
    std::cout << when << ":" << std::endl;
    for (const auto &[name, label] : files)
      std::cout << "  " << label << ": "
                << (std::filesystem::exists("results/scene/" + name) ? "there" : "removed") << std::endl;
  };

  tests::write_file("scene.prm", scene(1));
  std::cout << "run: " << tests::run_warpchol({"scene.prm"}) << std::endl;
  show("after the next run");

  tests::write_file("results/scene/checkpoint.bin.tmp." + dead, "half a checkpoint");
  tests::write_file("scene.prm", scene(2));
  std::cout << "resume: " << tests::run_warpchol({"scene.prm", "--resume"}) << std::endl;
  std::cout << "after --resume: checkpoint.bin.tmp.DEAD: "
            << (std::filesystem::exists("results/scene/checkpoint.bin.tmp." + dead) ? "there" : "removed")
            << std::endl;
}
