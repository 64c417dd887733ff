// A process allowed one core writes each VTU file at once, inside VtuSeries::write(): in
// the background the file would take the core of the steps, whose measured seconds (which
// the automatic strategy's fall-back compares with exact steps) would then count its
// writing. With two cores allowed the file is written beside the caller, and finish()
// waits for it; either way the same bytes.

#include "simulation_tests.h"

#include <warpchol/app/output.h>
#include <warpchol/app/parameters.h>
#include <warpchol/app/scene.h>

#include <sched.h>

#include <filesystem>
#include <fstream>
#include <iterator>

using namespace warpchol;

namespace
{
  /** Allow this process @p cores of the cores it has (the first ones); false if it has fewer. */
  bool allow_cores(const cpu_set_t &all, const int cores)
  {
    cpu_set_t set;
    CPU_ZERO(&set);
    int taken = 0;
    for (int cpu = 0; cpu < CPU_SETSIZE && taken < cores; ++cpu)
      if (CPU_ISSET(cpu, &all))
        {
          CPU_SET(cpu, &set);
          ++taken;
        }
    return taken == cores && sched_setaffinity(0, sizeof set, &set) == 0;
  }

  std::string contents(const std::string &file)
  {
    std::ifstream in(file, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
} // namespace

int main()
{
  tests::write_file("torus.prm", "subsection Mesh\n  set Source = torus\n  set Torus toroidal cells = 8\nend\n"
                                 "subsection Output\n  set Print timings = false\nend\n");
  const app::AllParameters parameters("torus.prm");
  app::Scene               scene(parameters);
  app::BodySnapshot        snapshot;
  snapshot.body          = &scene.body();
  snapshot.displacements = scene.integrator().displacements();
  snapshot.velocities    = scene.integrator().velocities();
  snapshot.record        = scene.model().rerotation_record();

  cpu_set_t all;
  CPU_ZERO(&all);
  sched_getaffinity(0, sizeof all, &all);
  std::string one_core_bytes;
  for (const int cores : {1, 2})
    {
      if (!allow_cores(all, cores))
        {
          // A machine of one core: what two cores would do cannot be shown here.
          std::cout << cores << " cores: not available, skipped\n";
          continue;
        }
      std::cout << cores << (cores == 1 ? " core" : " cores") << ": written in the background: "
                << (app::VtuSeries::writes_in_background() ? "yes" : "no") << "\n";
      const std::string directory = "series_" + std::to_string(cores);
      std::filesystem::create_directories(directory);
      app::VtuSeries series(directory, "torus");
      series.write(0, 0., {snapshot});
      const std::string file = directory + "/torus-00000.vtu";
      if (cores == 1)
        std::cout << "1 core: the file is there when write() returns: "
                  << (std::filesystem::exists(file) && std::filesystem::file_size(file) > 0 ? "yes" : "no") << "\n";
      series.finish();
      if (cores == 1)
        one_core_bytes = contents(file);
      else
        std::cout << "2 cores: after finish(), the same bytes as with 1: "
                  << (contents(file) == one_core_bytes ? "yes" : "no") << "\n";
    }
}
