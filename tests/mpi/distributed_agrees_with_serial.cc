// A scene run distributed on 2 ranks (mpirun -np 2 warpchol FILE.prm: METIS partition,
// Trilinos or PETSc matrices) agrees with the serial run of the same .prm, warpchol's
// direct factor on one process, to the solver's tolerance: the energies of every step
// (kinetic, elastic, potential, tool's springs), for the linear, corotational, stiffness
// warping and WCC models, with Trilinos CG + ML AMG at tolerance 1e-12 and with MUMPS.
// Also: a run on one rank with --distributed, Strategy = auto taken as partial with a
// warning, and the entries a distributed run refuses.
//
// mpirun comes from CMake (WARPCHOL_MPIEXEC): tests/CMakeLists.txt adds this test only
// where it was found, and says so otherwise.

#include "../simulation_tests.h"
#include "../tests.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

extern char **environ;

namespace
{
  /**
   * Run "[mpirun -np N] warpchol ARGS", its standard output and error to @p log; return
   * its exit status. Root may run mpirun (CI runs as root); more ranks than cores are fine.
   */
  int spawn(const unsigned int n_ranks, const std::vector<std::string> &arguments, const std::string &log)
  {
    std::vector<std::string> words;
    if (n_ranks > 0)
      words = {WARPCHOL_MPIEXEC, "-np", std::to_string(n_ranks)};
    words.push_back(WARPCHOL_PROGRAM);
    words.insert(words.end(), arguments.begin(), arguments.end());
    std::vector<char *> argv;
    for (auto &word : words)
      argv.push_back(word.data());
    argv.push_back(nullptr);
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    setenv("OMPI_MCA_rmaps_base_oversubscribe", "1", 1);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    pid_t child = 0;
    if (posix_spawn(&child, argv[0], &actions, nullptr, argv.data(), environ) != 0)
      return -1;
    posix_spawn_file_actions_destroy(&actions);
    int status = 0;
    waitpid(child, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  /** The columns of a log.csv by name, one value per step. */
  std::map<std::string, std::vector<double>> read_log(const std::string &filename)
  {
    std::ifstream                               in(filename);
    std::string                                 line;
    std::vector<std::string>                    names;
    std::map<std::string, std::vector<double>> columns;
    std::getline(in, line);
    std::istringstream header(line);
    for (std::string name; std::getline(header, name, ',');)
      names.push_back(name);
    while (std::getline(in, line))
      {
        std::istringstream row(line);
        std::string        value;
        for (std::size_t k = 0; k < names.size() && std::getline(row, value, ','); ++k)
          columns[names[k]].push_back(value.empty() ? NAN : std::atof(value.c_str()));
      }
    return columns;
  }

  /** max over steps of |a - b| / max over steps of |b|, for each energy. */
  double energy_difference(const std::map<std::string, std::vector<double>> &a,
                           const std::map<std::string, std::vector<double>> &b, unsigned int &n_steps)
  {
    double worst = 0;
    n_steps      = 0;
    for (const std::string name : {"kinetic_energy", "elastic_energy", "potential_energy", "tool_energy"})
      {
        const auto found_a = a.find(name), found_b = b.find(name);
        if (found_a == a.end() || found_b == b.end() || found_a->second.size() != found_b->second.size())
          return INFINITY;
        double difference = 0, scale = 0;
        for (std::size_t k = 0; k < found_a->second.size(); ++k)
          {
            difference = std::max(difference, std::abs(found_a->second[k] - found_b->second[k]));
            scale      = std::max(scale, std::abs(found_b->second[k]));
          }
        worst   = std::max(worst, scale > 0 ? difference / scale : difference);
        n_steps = found_a->second.size();
      }
    return worst;
  }

  std::string scene(const std::string &model, const std::string &name, const std::string &solver)
  {
    return tests::small_torus_scene(model) +
           "subsection Time stepping\n  set Number of steps = 15\n  set Time step = 0.01\n"
           "  set Rayleigh mass = 0.1\n  set Rayleigh stiffness = 0.1\nend\n"
           "subsection Output\n  set Directory = results\n  set Scene = " + name +
           "\n  set Write log = true\n  set VTU interval = 5\n  set Progress = off\nend\n"
           "subsection Distributed\n  set Linear solver = " + solver +
           // MUMPS, a direct solver, has no tolerance (it would be warned about).
           (solver == "amg_cg" ? "\n  set Tolerance = 1e-12" : "") + "\nend\n";
  }
} // namespace

int main()
{
  const std::vector<std::pair<std::string, std::string>> models = {
    {"linear", "  set Type = linear\n"},
    {"corotational", "  set Type = corotational\n"},
    {"stiffness_warping", "  set Type = stiffness_warping\n"},
    {"warp_canceling", "  set Type = warp_canceling\n  set Rerotation threshold = 0.3\n"}};
  for (const auto &[label, model] : models)
    for (const std::string solver : {"amg_cg", "mumps"})
      {
        const std::string name = label + "_" + solver;
        tests::write_file(name + ".prm", scene(model, name, solver));
        // The serial run: warpchol's own factor, in this process, without the Distributed
        // subsection, which it would name as ignored.
        tests::write_file(name + "_serial.prm",
                          tests::without_subsection(scene(model, name + "_serial", solver), "Distributed"));
        const std::string serial = tests::run_warpchol({name + "_serial.prm"});
        const int status = spawn(2, {name + ".prm"}, name + ".out");
        unsigned int n_steps = 0;
        const double difference =
          energy_difference(read_log("results/" + name + "/log.csv"), read_log("results/" + name + "_serial/log.csv"), n_steps);
        std::ifstream      pvd("results/" + name + "/" + name + ".pvd");
        std::ostringstream pvd_text;
        pvd_text << pvd.rdbuf();
        unsigned int n_records = 0;
        for (std::size_t at = pvd_text.str().find(".pvtu"); at != std::string::npos;
             at             = pvd_text.str().find(".pvtu", at + 1))
          ++n_records;
        const bool pieces = std::ifstream("results/" + name + "/" + name + "-00015.0.vtu").good() &&
                            std::ifstream("results/" + name + "/" + name + "-00015.1.vtu").good() &&
                            std::ifstream("results/" + name + "/" + name + "-00015.pvtu").good();
        std::cout << label << ", " << solver << ", 2 ranks: exit " << status << ", serial " << serial << ", "
                << n_steps << " steps, energies agree to 1e-8: " << (difference < 1e-8 ? "yes" : "NO")
                << ", PVD records " << n_records << ", pieces of both ranks: " << (pieces ? "yes" : "NO")
                << std::endl;
        if (!(difference < 1e-8))
          std::cout << "  relative difference " << difference << std::endl;
      }

  // One rank, distributed by request: the same engines, the same results.
  {
    tests::write_file("one_rank.prm", scene("  set Type = corotational\n", "one_rank", "amg_cg"));
    const int    status     = spawn(0, {"one_rank.prm", "--distributed"}, "one_rank.out");
    unsigned int n_steps    = 0;
    const double difference = energy_difference(read_log("results/one_rank/log.csv"),
                                                read_log("results/corotational_amg_cg_serial/log.csv"), n_steps);
    std::cout << "corotational, amg_cg, 1 rank (--distributed): exit " << status << ", energies agree to 1e-8: "
            << (difference < 1e-8 ? "yes" : "NO") << std::endl;
  }

  // Strategy = auto (the default scene's), which a distributed run does not have: it runs
  // as partial, the WCC system solved by the distributed solver, and says so in one line.
  {
    tests::write_file("auto.prm", scene("  set Type = warp_canceling\n  set Rerotation threshold = 0.3\n"
                                        "  set Strategy = auto\n",
                                        "auto", "amg_cg"));
    const int     status = spawn(2, {"auto.prm"}, "auto.out");
    std::ifstream in("auto.out");
    std::string   line, warning;
    unsigned int  n_warnings = 0;
    while (std::getline(in, line))
      if (line.rfind("warpchol: warning", 0) == 0 && n_warnings++ == 0)
        warning = line;
    unsigned int n_steps    = 0;
    const double difference = energy_difference(read_log("results/auto/log.csv"),
                                                read_log("results/warp_canceling_amg_cg/log.csv"), n_steps);
    std::cout << "warp_canceling, Strategy = auto, 2 ranks: exit " << status << ", warnings " << n_warnings << ": "
              << warning.substr(std::min(warning.size(), warning.find("auto.prm"))) << "; " << n_steps
              << " steps as partial's to 1e-8: " << (difference < 1e-8 ? "yes" : "NO") << std::endl;
  }

  // What a distributed run does not do: one line, naming the entry, exit status 2.
  for (const auto &[entry, text] : std::vector<std::pair<std::string, std::string>>{
         {"Output/Checkpoint interval", "subsection Output\n  set Checkpoint interval = 5\nend\n"},
         {"Bodies/Number of bodies", "subsection Bodies\n  set Number of bodies = 2\n  set Spacing = 1, 0, 0\nend\n"},
         {"Distributed/Linear solver", "subsection Distributed\n  set Linear solver = pardiso\nend\n"}})
    {
      tests::write_file("refused.prm", tests::small_torus_scene("  set Type = corotational\n") + text);
      const int     status = spawn(2, {"refused.prm"}, "refused.out");
      std::ifstream in("refused.out");
      std::string   line, first;
      unsigned int  n_lines = 0;
      // mpirun adds its own banner about the exit status: warpchol's lines are ours.
      while (std::getline(in, line))
        if (line.rfind("warpchol", 0) == 0)
          {
            if (n_lines++ == 0)
              first = line;
          }
      std::cout << entry << ": exit " << status << ", lines of warpchol " << n_lines << ": "
              << first.substr(first.find("refused.prm")) << std::endl;
    }
}
