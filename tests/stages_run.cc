// A scene runs only the stages its settings need, and the summary lists them: no rotations
// for the linear model, no estimate for WCC at thresholds 0 and inf, no factorization in a
// step where no element changed (the first one, at rest), no tool springs without a tool,
// no CG without an iterating strategy, no log, VTU or reference run unless asked for. With
// Print timings, the summary's table has the same stages, and their shares and "other"
// make up the run.

#include "simulation_tests.h"

#include <warpchol/app/simulation.h>

#include <sstream>

using namespace warpchol;

namespace
{
  /** What a scene differs in: the body of "subsection Model" and the optional parts. */
  struct Variant
  {
    std::string model;
    bool        tool    = true;
    bool        damping = true;
    /** The body of "subsection Output" beyond the defaults of these tests. */
    std::string output;
  };

  /** The small torus of the simulation tests, held and pulled, 5 steps. */
  std::string scene(const Variant &variant)
  {
    std::string text = tests::small_torus_scene(variant.model);
    if (!variant.tool)
      text = tests::without_subsection(text, "Tool");
    if (!variant.damping)
      for (const std::string entry : {"  set Rayleigh mass = 0.1\n", "  set Rayleigh stiffness = 0.1\n"})
        text.erase(text.find(entry), entry.size());
    // Not "output": the test driver writes a file of that name here.
    return text + "subsection Time stepping\n  set Number of steps = 5\nend\n"
                  "subsection Output\n"
                  "  set Directory = results\n"
                  "  set Progress = off\n"
                  "  set Print timings = false\n" +
           variant.output + "end\n";
  }

  /** Run @p variant and return its summary. */
  std::string summary_of(const Variant &variant, const std::string &name = "scene")
  {
    tests::write_file(name + ".prm", scene(variant));
    app::Simulation    simulation{app::AllParameters(name + ".prm")};
    std::ostringstream out;
    simulation.run(out);
    return out.str();
  }

  /** The line of @p summary that starts with "  stages: ", without that start. */
  std::string stages_line(const std::string &summary)
  {
    const std::string start    = "\n  stages: ";
    const auto        position = summary.find(start);
    if (position == std::string::npos)
      return "(no stages line)";
    const auto begin = position + start.size();
    return summary.substr(begin, summary.find('\n', begin) - begin);
  }

  void print_stages(const std::string &label, const Variant &variant)
  {
    std::cout << label << ": " << stages_line(summary_of(variant)) << std::endl;
  }
} // namespace

int main()
{
  const std::string wcc = "  set Type = warp_canceling\n  set Rerotation threshold = 0.3\n";

  print_stages("linear", {"  set Type = linear\n"});
  print_stages("stiffness warping", {"  set Type = stiffness_warping\n"});
  print_stages("WCC, threshold 0.3", {wcc});
  print_stages("WCC, threshold 0", {"  set Type = warp_canceling\n  set Rerotation threshold = 0\n"});
  print_stages("WCC, threshold inf", {"  set Type = warp_canceling\n  set Rerotation threshold = inf\n"});
  print_stages("corotational", {"  set Type = corotational\n"});
  print_stages("WCC, preconditioned CG", {wcc + "  set Strategy = preconditioned\n"});
  print_stages("WCC, no tool", {wcc, false});
  // Rayleigh damping lies in A alone (its coefficients): no stage of its own either way.
  print_stages("WCC, no damping", {wcc, true, false});
  print_stages("WCC, log, VTU and the corotational run",
               {wcc, true, true,
                "  set Write log = true\n  set VTU interval = 2\n  set Compare with corotational = true\n"});

  // The run's totals: WCC factors only in the steps with an update (not in the first, at
  // rest); each stage is timed at most once a step, the output ones when asked.
  {
    tests::write_file("wcc.prm", scene({wcc, true, true, "  set VTU interval = 2\n"}));
    app::Simulation    simulation{app::AllParameters("wcc.prm")};
    std::ostringstream out;
    simulation.run(out);
    const auto &totals = simulation.totals();
    tests::check("WCC: a factorization in every step with an update and no other",
                 totals.stages.runs(fem::stage::factorization) == totals.steps_with_rerotations);
    tests::check("WCC: no update in the first step", totals.steps_with_rerotations < totals.steps);
    tests::check("WCC: rotations and the solve in every step",
                 totals.stages.runs(fem::stage::rotations) == totals.steps &&
                   totals.stages.runs(fem::stage::solve) == totals.steps);
    tests::check("WCC: a VTU output per file (initial state and steps 2, 4)",
                 totals.stages.runs(app::stage::vtu_output) == 3);
    tests::check("WCC: the stages take no longer than the run",
                 totals.stages.total_seconds() <= totals.run_seconds);
  }

  // With Print timings: a table of the same stages, whose shares and "other" add up to
  // the run (each printed to 2 digits).
  {
    const std::string summary = summary_of({wcc, true, true, "  set Print timings = true\n"}, "timed");
    std::istringstream lines(summary);
    std::string        line, names;
    bool               in_table = false;
    double             shares   = 0;
    while (std::getline(lines, line))
      {
        if (line.rfind("  stages:", 0) == 0)
          {
            in_table = true;
            continue;
          }
        if (!in_table || line.rfind("    ", 0) != 0)
          {
            in_table = false;
            continue;
          }
        // "    NAME (22 wide)  RUNS  SECONDS  SHARE %"
        std::string name = line.substr(4, 22);
        name.erase(name.find_last_not_of(' ') + 1);
        if (name == "time steps")
          continue;
        std::istringstream numbers(line.substr(26));
        std::string        first;
        double             seconds = 0, share = 0;
        numbers >> first;
        if (name != "other")
          numbers >> seconds;
        numbers >> share;
        shares += share;
        if (name != "other")
          names += (names.empty() ? "" : ", ") + name;
      }
    std::cout << "WCC, timed: " << names << std::endl;
    tests::check_below("WCC, timed: |sum of the shares - 100 %|", std::abs(shares - 100), 1);
  }
}
