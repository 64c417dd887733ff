// Output/Progress takes auto, on and off, and the words of the other switches: true and
// yes mean on, false and no off. Anything else is refused naming the file and line.

#include "simulation_tests.h"

int main()
{
  for (const std::string value : {"auto", "on", "off", "true", "false", "yes", "no", "sometimes"})
    {
      const std::string file = "progress_" + value + ".prm";
      tests::write_file(file, "subsection Output\n  set Progress = " + value + "\nend\n");
      tests::print_result_or_error("Progress = " + value,
                                   [&] { return warpchol::app::AllParameters(file).output.progress; });
    }
}
