// Every bad instrument path stops warpchol with one line naming the path file and the line
// (exit status 2): times that do not increase, NaN and infinity, a value that is no number,
// missing and extra columns, no sample, a path that ends before its use or starts after
// it, a path given with a velocity; for the tool, the blade and the jaws.

#include "simulation_tests.h"

namespace
{
  /** A small box, 10 steps of 0.01 s, with @p extra appended. */
  std::string scene(const std::string &extra)
  {
    return "subsection Mesh\n  set Source = box\n  set Box subdivisions = 4, 1, 1\nend\n"
           "subsection Time stepping\n  set Number of steps = 10\nend\n"
           "subsection Fixed vertices\n  set Region = box\n  set Box lower corner = -1, -1, -1\n"
           "  set Box upper corner = 1e-6, 1, 1\nend\n"
           "subsection Output\n  set Print timings = false\n  set Write log = false\nend\n" +
           extra;
  }

  const std::string good_blade = "time, start x, start y, start z, end x, end y, end z\n"
                                 "0.0, 0.2, -1, 0.05, 0.2, 1, 0.05\n"
                                 "0.1, 0.3, -1, 0.05, 0.3, 1, 0.05\n";

  std::string cut(const std::string &file, const std::string &extra = "")
  {
    return "subsection Cut\n  set Path file = " + file + "\n  set Start time = 0\n  set Duration = 0.1\n" + extra +
           "end\n";
  }

  std::string grasp(const std::string &file, const std::string &times = "  set Grasp time = 0.02\n")
  {
    return "subsection Grasp 2\n  set Path file = " + file + "\n  set Sphere radius = 0.06\n" + times + "end\n";
  }

  std::string tool(const std::string &file)
  {
    return "subsection Tool\n  set Region = sphere\n  set Sphere center = 0.4, 0.05, 0.05\n"
           "  set Sphere radius = 0.06\n  set Spring stiffness = 20\n  set Path file = " + file + "\nend\n";
  }

  void run(const std::string &label, const std::string &path_text, const std::string &sections)
  {
    tests::write_file("path.csv", path_text);
    tests::write_file("scene.prm", scene(sections));
    std::cout << label << ": " << tests::run_warpchol({"scene.prm"}) << std::endl;
  }
} // namespace

int main()
{
  run("good blade path", good_blade, cut("path.csv"));
  run("times not increasing", good_blade + "0.1, 0.4, -1, 0.05, 0.4, 1, 0.05\n", cut("path.csv"));
  run("time going back", "# recorded\n0, 0.4, 0.05, 0.05\n0.05, 0.4, 0.06, 0.05\n0.04, 0.4, 0.07, 0.05\n"
                         "0.2, 0.4, 0.08, 0.05\n", tool("path.csv"));
  run("NaN", "0, 0.2, -1, 0.05, 0.2, 1, 0.05\n0.1, nan, -1, 0.05, 0.3, 1, 0.05\n", cut("path.csv"));
  run("infinity", "0, 0.4, 0.05, 0.05\n0.1, 0.4, inf, 0.05\n", tool("path.csv"));
  run("not a number", "0, 0.4, 0.05, 0.05\n0.1, 0.4, 0.05x, 0.05\n", tool("path.csv"));
  run("empty value", "0, 0.4, 0.05, 0.05\n0.1, 0.4, , 0.05\n", tool("path.csv"));
  run("missing columns", "0, 0.2, -1, 0.05, 0.2, 1\n", cut("path.csv"));
  run("a blade given as a point", "0, 0.4, 0.05, 0.05\n0.2, 0.4, 0.05, 0.05\n", cut("path.csv"));
  run("extra column", "0, 0.4, 0.05, 0.05, 1\n", grasp("path.csv"));
  run("no sample", "time, x, y, z\n# nothing recorded\n", tool("path.csv"));
  run("ends before the run", "0, 0.4, 0.05, 0.05\n0.05, 0.4, 0.06, 0.05\n", tool("path.csv"));
  run("ends before the cut", "0, 0.2, -1, 0.05, 0.2, 1, 0.05\n0.08, 0.3, -1, 0.05, 0.3, 1, 0.05\n",
      cut("path.csv"));
  run("starts after the grasp", "0.03, 0.4, 0.05, 0.05\n0.2, 0.4, 0.06, 0.05\n", grasp("path.csv"));
  run("ends before the release", "0, 0.4, 0.05, 0.05\n0.05, 0.4, 0.06, 0.05\n",
      grasp("path.csv", "  set Grasp time = 0.02\n  set Release time = 0.08\n"));
  run("a path and a velocity", good_blade, cut("path.csv", "  set Velocity = 0, 0, 1\n"));
  run("missing file", good_blade, cut("no_such_path.csv"));
  run("binary file", std::string("\x7f" "ELF\x02\x01\x01\0\0\0", 10), cut("path.csv"));
}
