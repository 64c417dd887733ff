// The plot of the error-against-time study: the data the gnuplot script carries (the
// configurations by group, a diverged run clipped at 1 with its error in its label, the
// Pareto fronts of the worst vertex's and of the RMS error, the reference's time), and
// without gnuplot on the PATH one line saying so, the script written all the same.

#include "tests.h"

#include <warpchol/reports/error_time_plot.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>

using namespace warpchol;

int main()
{
  app::ErrorTimePlot plot("torus: 3 configurations", "corotational", 0.04);
  plot.add({"WCC partial", "0.3", 0.030, 2e-2, 5e-3});
  plot.add({"WCC partial", "inf", 0.010, 3e+40, 1e+39}); // diverged
  plot.add({"WCC auto", "1", 0.012, 3e-3, 1e-3});
  plot.add({"WCC auto", "0.3", 0.020, 4e-3, 5e-4}); // on the RMS front only

  // The data blocks of the script, and where the reference's line stands.
  std::istringstream script(plot.script("plot.png"));
  bool               in_block = false;
  for (std::string line; std::getline(script, line);)
    {
      if (line.find("<< EOD") != std::string::npos || line.find("# WCC") == 0)
        in_block = true;
      if (in_block || line.find("set arrow 1") == 0 || line.find("set yrange") == 0)
        std::cout << line << std::endl;
      if (line == "EOD")
        in_block = false;
    }

  // No gnuplot: the script and one line, no plot.
  setenv("PATH", "", 1);
  std::ostringstream messages;
  const bool         plotted = plot.write("plot.gp", "plot.png", messages);
  std::cout << messages.str();
  tests::check("no plot without gnuplot", !plotted && !std::filesystem::exists("plot.png"));
  tests::check("the script is written all the same", std::filesystem::exists("plot.gp"));
}
