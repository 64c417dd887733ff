// StageTimes: totals over steps keep the order of a step, whichever step first ran a
// stage; runs and seconds add up; a stage that never ran is absent.

#include "tests.h"

#include <warpchol/base/stage_times.h>

using namespace warpchol;

namespace
{
  StageTimes step(const std::vector<std::string> &names)
  {
    StageTimes times;
    for (const auto &name : names)
      times.add(name, 1.0);
    return times;
  }
} // namespace

int main()
{
  StageTimes run;
  // The first step changes nothing (no assembly, no factorization); the second does.
  run.add(step({"rotations", "error estimate", "solve"}));
  run.add(step({"rotations", "error estimate", "assembly", "factorization", "solve"}));
  run.add("log", 0.5);
  run.add("log", 0.25, 0);
  std::cout << "stages: " << run.names() << std::endl;

  tests::check("rotations: 2 runs, 2 s", run.runs("rotations") == 2 && run.seconds("rotations") == 2.0);
  tests::check("factorization: 1 run, 1 s",
               run.runs("factorization") == 1 && run.seconds("factorization") == 1.0);
  tests::check("log: time added to its run without a run of its own",
               run.runs("log") == 1 && run.seconds("log") == 0.75);
  tests::check("a stage that never ran is absent",
               !run.ran("tool springs") && run.seconds("tool springs") == 0.0 && run.runs("tool springs") == 0);
  tests::check("total: 8.75 s", run.total_seconds() == 8.75);

  // A stage new to the totals that comes first in a step goes first.
  run.add(step({"initial guess", "rotations"}));
  std::cout << "stages: " << run.names() << std::endl;

  // A timer records one run, once, however it ends.
  StageTimes timed;
  {
    StageTimer timer(timed, "solve");
    timer.stop();
  }
  tests::check("a timer stopped early records one run", timed.runs("solve") == 1);
}
