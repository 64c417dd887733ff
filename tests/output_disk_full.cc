// A result that cannot be written is one line naming the file, the system's reason and the
// bytes, with exit status 3, and what was written before stays whole:
// - /dev/full (every write fails with ENOSPC, as on a full disk) through the atomic-file
//   helper, with a plain writer and with deal.II's DataOut (whose own exception, many lines
//   and a stack trace, must not surface); the device itself is written, not replaced;
// - a file size limit (RLIMIT_FSIZE: writes past it fail with EFBIG) on a regular file:
//   the earlier version stays and no temporary file is left;
// - a whole run under that limit: the first VTU file fails, warpchol exits with 3, the
//   files of an earlier run stay as they were;
// - an output directory that cannot be created, reported before the mesh is even read.

#include "simulation_tests.h"

#include <warpchol/app/simulation.h>
#include <warpchol/base/atomic_file.h>

#include <deal.II/grid/grid_generator.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/data_out.h>

#include <sys/resource.h>
#include <sys/stat.h>

#include <csignal>
#include <filesystem>
#include <regex>
#include <sstream>

using namespace warpchol;

namespace
{
  /** The message with the byte counts that depend on deal.II's output replaced by N. */
  std::string without_sizes(const std::string &message)
  {
    return std::regex_replace(message, std::regex("of [0-9]+ bytes"), "of N bytes");
  }

  /** Run "warpchol ARGUMENTS": "message [exit S]", the message without its newline. */
  std::string run(const std::vector<std::string> &arguments)
  {
    return tests::run_warpchol(arguments);
  }

  /** The names of the files in @p directory that hold ".tmp." (temporaries left behind). */
  unsigned int temporaries_in(const std::string &directory)
  {
    unsigned int n = 0;
    for (const auto &entry : std::filesystem::directory_iterator(directory))
      n += entry.path().filename().string().find(".tmp.") != std::string::npos;
    return n;
  }

  /** Limit the size of the files this process writes to @p bytes (the soft limit). */
  void limit_file_size(const rlim_t bytes)
  {
    rlimit limit;
    getrlimit(RLIMIT_FSIZE, &limit);
    limit.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &limit);
  }
} // namespace

int main()
{
  // Past the limit, write(2) fails with EFBIG instead of the process receiving SIGXFSZ.
  std::signal(SIGXFSZ, SIG_IGN);
  rlimit unlimited;
  getrlimit(RLIMIT_FSIZE, &unlimited);

  std::cout << "-- /dev/full" << std::endl;
  tests::expect_error("100000 bytes", [] {
    write_file_atomically("/dev/full", [](std::ostream &out) {
      for (unsigned int i = 0; i < 10000; ++i)
        out << "123456789\n";
    });
  });
  tests::expect_error("deal.II's VTU writer", [] {
    try
      {
        dealii::Triangulation<3> triangulation;
        dealii::GridGenerator::hyper_cube(triangulation);
        triangulation.refine_global(2);
        dealii::Vector<double> values(triangulation.n_active_cells());
        dealii::DataOut<3>     data_out;
        data_out.attach_triangulation(triangulation);
        data_out.add_data_vector(values, "values", dealii::DataOut<3>::type_cell_data);
        data_out.build_patches();
        write_file_atomically("/dev/full", [&](std::ostream &out) { data_out.write_vtu(out); });
      }
    catch (const Error &error)
      {
        throw Error(without_sizes(error.what()));
      }
  });
  struct stat status;
  tests::check("/dev/full is still a character device",
               stat("/dev/full", &status) == 0 && S_ISCHR(status.st_mode));

  std::cout << "-- a file size limit of 1000 bytes" << std::endl;
  std::filesystem::create_directories("limited");
  write_file_atomically("limited/kept.txt", [](std::ostream &out) { out << "the first version\n"; });
  limit_file_size(1000);
  tests::expect_error("5000 bytes", [] {
    write_file_atomically("limited/kept.txt", [](std::ostream &out) { out << std::string(5000, 'x'); });
  });
  limit_file_size(unlimited.rlim_cur);
  tests::check("the earlier version is kept", tests::read_file("limited/kept.txt") == "the first version\n");
  tests::check("no temporary file is left", temporaries_in("limited") == 0);

  std::cout << "-- a run" << std::endl;
  const std::string scene = "subsection Mesh\n  set Source = box\n  set Box subdivisions = 2, 1, 1\nend\n"
                            "subsection Time stepping\n  set Number of steps = 3\nend\n"
                            "subsection Output\n  set Directory = results\n  set Scene = box\n"
                            "  set VTU interval = 1\n  set Write log = true\n  set Progress = off\n"
                            "  set Print timings = false\nend\n";
  tests::write_file("box.prm", scene);
  std::cout << "unlimited: " << run({"box.prm"}) << std::endl;
  const std::string first_vtu = tests::read_file("results/box/box-00000.vtu");
  const std::string first_pvd = tests::read_file("results/box/box.pvd");
  limit_file_size(2000);
  std::cout << "VTU files over the limit: " << without_sizes(run({"box.prm"})) << std::endl;
  limit_file_size(unlimited.rlim_cur);
  tests::check("the earlier run's VTU file and series are kept",
               first_vtu.size() > 2000 && tests::read_file("results/box/box-00000.vtu") == first_vtu &&
                 tests::read_file("results/box/box.pvd") == first_pvd);
  tests::check("no temporary file is left", temporaries_in("results/box") == 0);

  std::cout << "-- the output directory, checked first" << std::endl;
  tests::write_file("a_file", "not a directory\n");
  // The box's Mesh subsection replaced by a missing file's (a file uses none of the box's entries).
  std::string file_scene = scene;
  file_scene.replace(0, file_scene.find("end\n") + 4,
                     "subsection Mesh\n  set Source = file\n  set File = no_such_mesh.msh\nend\n");
  tests::write_file("unwritable.prm", file_scene + "subsection Output\n  set Directory = a_file\nend\n");
  std::cout << "a file in the way (and a missing mesh): " << run({"unwritable.prm"}) << std::endl;
  tests::check("nothing was created", std::filesystem::is_regular_file("a_file"));
}
