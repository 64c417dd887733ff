// Checkpoint and resume: a run killed mid-way (SIGKILL, as a crash or a power cut would
// stop it) and resumed with "--resume" ends, to the bit, where the same run never
// stopped ends: positions, velocities, the matrix A its model carries, the log's values
// and the summary. Scenes: WCC with partial refactorization beside its corotational
// reference run; WCC with the factor refreshed below the top only (a stale factor, in
// single precision, as CG's preconditioner); WCC refreshing its factor on a thread of its
// own at a fixed lag, the checkpoint taken while a refresh is in flight; WCC with cuts and
// a grasp; WCC after a material change that left plastic strains; WCC adapting its
// threshold to a target error; two bodies, one of them factored by CHOLMOD. Then what
// resume refuses.

#include "simulation_tests.h"

#include <warpchol/app/simulation.h>
#include <warpchol/cholesky/blas.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <thread>

extern char **environ;

namespace
{
  /**
   * The small torus of the simulation tests, for @p n_steps steps, with a log, VTU files
   * and a checkpoint every 10 steps; @p extra sets more entries.
   */
  std::string scene(const std::string &model_section, const std::string &extra, const unsigned int n_steps,
                    const bool compare_with_corotational = false)
  {
    return tests::small_torus_scene(model_section) +
           "subsection Time stepping\n"
           "  set Number of steps = " + std::to_string(n_steps) + "\n"
           "end\n" + extra +
           "subsection Output\n"
           "  set Directory = results\n"
           "  set VTU interval = 10\n"
           "  set Write log = true\n"
           "  set Print timings = false\n"
           "  set Progress = off\n"
           "  set Checkpoint interval = 10\n" +
           (compare_with_corotational ? "  set Compare with corotational = true\n" : "") +
           "end\n";
  }

  /** What a run ends with, to be compared bit for bit. */
  struct FinalState
  {
    std::vector<std::vector<warpchol::fem::Vector3>> positions, velocities;
    std::vector<std::vector<double>>                 matrices;
    std::string                                      log_values;
    std::string                                      summary;
  };

  /** The log without its columns of seconds (which differ from run to run). */
  std::string log_without_times(const std::string &filename)
  {
    std::istringstream lines(tests::read_file(filename));
    std::string        header, line, result;
    std::getline(lines, header);
    std::vector<bool> is_time;
    std::istringstream columns(header);
    for (std::string name; std::getline(columns, name, ',');)
      is_time.push_back(name.rfind("t_", 0) == 0);
    while (std::getline(lines, line))
      {
        std::istringstream cells(line);
        std::size_t        k = 0;
        for (std::string cell; std::getline(cells, cell, ','); ++k)
          if (k >= is_time.size() || !is_time[k])
            result += cell + ",";
        result += "\n";
      }
    return result;
  }

  FinalState final_state(const warpchol::app::Simulation &simulation, const std::string &summary)
  {
    FinalState state;
    for (unsigned int i = 0; i < simulation.n_bodies(); ++i)
      {
        const auto &scene = simulation.scene(i);
        state.positions.push_back(scene.integrator().positions());
        state.velocities.push_back(scene.integrator().velocities());
        state.matrices.push_back(scene.model().system_matrix().csc().values);
      }
    const std::string directory = simulation.output_directory();
    state.log_values = log_without_times(directory + (simulation.n_bodies() == 1 ? "/log.csv" : "/log_body1.csv"));
    state.summary    = summary;
    return state;
  }

  template <typename T>
  bool same_bits(const std::vector<std::vector<T>> &a, const std::vector<std::vector<T>> &b)
  {
    if (a.size() != b.size())
      return false;
    for (std::size_t i = 0; i < a.size(); ++i)
      if (a[i].size() != b[i].size() ||
          std::memcmp(a[i].data(), b[i].data(), a[i].size() * sizeof(T)) != 0)
        return false;
    return true;
  }

  /**
   * Start the warpchol program on @p parameter_file, kill it with SIGKILL as soon as it
   * has written @p checkpoint, and return whether it was still running then.
   */
  bool run_and_kill(const std::string &parameter_file, const std::string &checkpoint)
  {
    std::string               program = WARPCHOL_PROGRAM;
    std::vector<std::string>  arguments{program, parameter_file};
    std::vector<char *>       argv;
    for (auto &argument : arguments)
      argv.push_back(argument.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
    pid_t child = 0;
    if (posix_spawn(&child, program.c_str(), &actions, nullptr, argv.data(), environ) != 0)
      throw std::runtime_error("cannot start " + program);
    posix_spawn_file_actions_destroy(&actions);
    int status = 0;
    while (!std::filesystem::exists(checkpoint))
      {
        if (waitpid(child, &status, WNOHANG) == child)
          return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    kill(child, SIGKILL);
    waitpid(child, &status, 0);
    return WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
  }

  void check_scene(const std::string &name, const std::string &model_section, const std::string &extra,
                   const bool compare_with_corotational = false)
  {
    std::cout << "scene " << name << std::endl;
    const std::string file = name + ".prm";
    const std::string directory = "results/" + name;
    std::filesystem::remove_all(directory);

    // Killed mid-way: it would run 10000 steps; the first checkpoint stops it.
    tests::write_file(file, scene(model_section, extra, 10000, compare_with_corotational));
    tests::check("  killed by SIGKILL while running, after its first checkpoint",
                 run_and_kill(file, directory + "/checkpoint.bin"));

    // Resumed, to 40 steps.
    tests::write_file(file, scene(model_section, extra, 40, compare_with_corotational));
    const warpchol::app::AllParameters parameters(file);
    std::ostringstream                 resumed_summary;
    warpchol::app::Simulation          resumed(parameters);
    resumed.resume();
    resumed.run(resumed_summary);
    const FinalState after_resume = final_state(resumed, resumed_summary.str());

    // The same run, never stopped.
    std::filesystem::remove_all(directory);
    std::ostringstream        whole_summary;
    warpchol::app::Simulation whole(parameters);
    whole.run(whole_summary);
    const FinalState uninterrupted = final_state(whole, whole_summary.str());

    tests::check("  positions identical to the bit", same_bits(after_resume.positions, uninterrupted.positions));
    tests::check("  velocities identical to the bit", same_bits(after_resume.velocities, uninterrupted.velocities));
    tests::check("  matrix A identical to the bit", same_bits(after_resume.matrices, uninterrupted.matrices));
    tests::check("  log identical (but its seconds), 40 rows",
                 after_resume.log_values == uninterrupted.log_values &&
                   std::count(uninterrupted.log_values.begin(), uninterrupted.log_values.end(), '\n') == 40);
    tests::check("  summary identical", after_resume.summary == uninterrupted.summary);
    tests::check("  PVD lists 5 files",
                 std::count_if(std::filesystem::directory_iterator(directory), {}, [](const auto &entry) {
                   return entry.path().extension() == ".vtu";
                 }) == 5 &&
                   tests::read_file(directory + "/" + name + ".pvd").find(name + "-00040.vtu") != std::string::npos);
    const std::string &summary = uninterrupted.summary;
    std::cout << "  " << summary.substr(summary.find("steps:"), summary.find('\n', summary.find("steps:")) - summary.find("steps:"))
              << std::endl;
  }
} // namespace

int main(int, char **argv)
{
  // The program that writes the checkpoint runs OpenBLAS's kernels for this CPU
  // (restarting itself to choose them): so must the runs here that it is compared with.
  warpchol::cholesky::blas::restart_with_blas_kernels_for_this_cpu(argv);
  // Its re-rotations' update or partial refactorization is a close call on some machines:
  // chosen at fixed rates, not by measured times (which a loaded machine changes after the
  // resume, and the two methods round apart).
  const std::string fixed_rates = "subsection Solver\n  set Change method = flops\nend\n";
  check_scene("partial", "  set Type = warp_canceling\n  set Rerotation threshold = 0.3\n", fixed_rates, true);
  check_scene("below_top",
              "  set Type = warp_canceling\n  set Rerotation threshold = 0.1\n  set Strategy = delayed_top\n"
              "  set Refresh interval = 7\n",
              "subsection Solver\n  set Preconditioner precision = single\nend\n");
  // A checkpoint at step 10 while the refresh started at step 9 is in flight (taken at 12).
  check_scene("background",
              "  set Type = warp_canceling\n  set Strategy = background\n  set Background lag = 3\n", "");
  // A checkpoint at step 10 between two cuts (the blade cuts from step 6 to step 15), and
  // a grasp that closes before it and opens after it.
  check_scene("cut",
              "  set Type = warp_canceling\n  set Rerotation threshold = 0.3\n",
              "subsection Cut\n  set Blade start = 0.31, -0.2, -0.15\n  set Blade end = 0.31, 0.2, -0.15\n"
              "  set Velocity = 0, 0, 3\n  set Start time = 0.05\n  set Duration = 0.1\nend\n"
              "subsection Grasp\n  set Sphere center = -0.3, 0, 0\n  set Sphere radius = 0.1\n"
              "  set Velocity = 0, 0.5, 0\n  set Duration = 0.2\n  set Grasp time = 0.03\n"
              "  set Release time = 0.25\nend\n");
  // A checkpoint at step 10 after a material change at step 6 that kept the strained
  // region's stress: the plastic strains it left go on from the checkpoint.
  check_scene("plastic", "  set Type = warp_canceling\n  set Rerotation threshold = 0.3\n",
              "subsection Material change\n  set Region = sphere\n  set Sphere center = 0.3, 0, 0\n"
              "  set Sphere radius = 0.12\n  set Time = 0.05\n  set Stiffness factor = 1e4\n"
              "  set Stress = continuous\nend\n"
              // Its updates are close calls: chosen at fixed rates, not by measured times.
              "subsection Solver\n  set Change method = flops\nend\n");
  check_scene("target_error",
              "  set Type = warp_canceling\n  set Rerotation threshold = 0.3\n  set Target error = 0.01\n", "");
  check_scene("two_bodies", "  set Type = warp_canceling\n",
              "subsection Bodies\n  set Number of bodies = 2\n  set Spacing = 1, 0, 0\n"
              "  set Models = warp_canceling, stiffness_warping\n  set Rerotation thresholds = 0.3, 0\n"
              "end\nsubsection Solver\n  set Backend = cholmod\nend\n");

  // What resume refuses, in one line each.
  const auto resume = [](const std::string &file) {
    warpchol::app::Simulation simulation{warpchol::app::AllParameters(file)};
    simulation.resume();
    std::ostringstream summary;
    simulation.run(summary);
  };
  tests::write_file("other.prm", scene("  set Type = warp_canceling\n  set Rerotation threshold = 0.5\n", "", 40));
  std::filesystem::create_directories("results/other");
  std::filesystem::copy_file("results/partial/checkpoint.bin", "results/other/checkpoint.bin",
                             std::filesystem::copy_options::overwrite_existing);
  tests::expect_error("another threshold", [&]() { resume("other.prm"); });
  tests::write_file("none.prm", scene("  set Type = linear\n", "", 40));
  std::filesystem::remove_all("results/none");
  tests::expect_error("no checkpoint", [&]() { resume("none.prm"); });
  tests::write_file("partial.prm",
                    scene("  set Type = warp_canceling\n  set Rerotation threshold = 0.3\n", fixed_rates, 40, true));
  // Where a checkpoint cut short is caught depends on its layout: the message says so.
  std::filesystem::resize_file("results/partial/checkpoint.bin", 5000);
  std::string cut_short_message;
  try
    {
      resume("partial.prm");
    }
  catch (const warpchol::InputError &error)
    {
      cut_short_message = error.what();
    }
  tests::check("cut short: refused, naming the file, as cut short",
               cut_short_message.rfind("results/partial/checkpoint.bin: checkpoint section", 0) == 0 &&
                 cut_short_message.find("cut short") != std::string::npos);
  tests::write_file("results/partial/checkpoint.bin", "# vtk DataFile Version 3.0\nnot a checkpoint\n");
  tests::expect_error("not a checkpoint", [&]() { resume("partial.prm"); });
}
