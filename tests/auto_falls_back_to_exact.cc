// auto never loses to the exact path (ExactFallback, models/step_strategy.h).
//
// First on given step costs, so that every decision is fixed: own steps that cost more than
// an exact step fall back (a probe of two exact steps while only the estimate is known,
// then a stretch whose retry costs 1 % of it), the stretch doubles while the own steps
// keep losing and starts from their loss again once they won; own steps that pay never
// fall back (those that cost more than half the estimate first measure the exact step by
// a probe), and own steps that refreshed a cut's columns do not weigh; a tie within the
// margin does not fall back (its probes come at doubling intervals), nor one own step
// held up among steps that pay, nor one dear window after a cheap one; own
// steps that lose within their spread are judged on a longer window; a retry whose step
// gives up its solve ends at once; a probe that measured the exact step on a slow
// stretch of the machine is measured again soon, and a stretch whose exact steps cost as
// much as the own steps that lost (the machine slowed down) ends early; over runs of 1000 and 10000 steps that
// lose by 30 % throughout, the steps before the first fall-back and the retries cost under
// 1 % (2 % over 100 steps).
//
// Then on scenes. Where nothing pays (every element's error over the re-rotation threshold, so
// every step re-rotates all of them, and CG to 1e-10: no step of auto's own is cheaper than an
// exact one, each pays the error estimate and the iterations on top) auto falls back, and
// a step of the fall-back runs the stages of the exact path's step (the corotational
// model's), no more: no error estimate, no initial guess of CG; after a stretch (1100 steps:
// longer than the longest) its own steps come back.
// The trajectory is the exact path's to within CG's tolerance. Where its own steps pay clearly (the fine torus, 14625 tets, at
// threshold inf: no element re-rotated, CG on the corotational matrix, about a fifth of an
// exact step) it does not fall back. Decisions on measured seconds: the scenes are built so
// that the margins are wide.

#include "simulation_tests.h"
#include "tests.h"

#include <warpchol/app/parameters.h>
#include <warpchol/app/scene.h>
#include <warpchol/models/warp_canceling_model.h>

using namespace warpchol;

namespace
{
  /**
   * Feed @p fallback @p n steps: exact ones cost @p exact_seconds, its own @p own_seconds
   * (which @p paid_for_a_change, if so); how many ran exact, and their total cost added to
   * @p total (if given).
   */
  unsigned int feed(fem::ExactFallback &fallback, const unsigned int n, const double own_seconds,
                    const double exact_seconds, double *total = nullptr, const bool paid_for_a_change = false)
  {
    unsigned int exact = 0;
    for (unsigned int step = 0; step < n; ++step)
      {
        const bool   runs_exact = fallback.runs_exact();
        const double seconds    = runs_exact ? exact_seconds : own_seconds;
        exact += runs_exact;
        if (total)
          *total += seconds;
        fallback.record_step(seconds, false, paid_for_a_change);
      }
    return exact;
  }

  void given_costs()
  {
    std::cout << "on given costs (window " << fem::ExactFallback::window << ", margin "
              << 100 * fem::ExactFallback::margin << " %, retry budget " << 100 * fem::ExactFallback::retry_budget
              << " %):" << std::endl;
    fem::ExactFallback losing;
    losing.set_exact_estimate(0.5);
    // Steps 1, 2 not counted; steps 3 and 4 lose more than an exact step (the estimate)
    // over (1 + margin) exact steps, two of them (one alone may have been held up by
    // something else): a probe of two exact steps (5, 6) measures 1.0.
    tests::check("  own steps that cost twice an exact one: exact from step 5",
                 feed(losing, 4, 2.0, 1.0) == 0 && losing.runs_exact());
    tests::check("  a probe of 2 exact steps measures the exact step",
                 feed(losing, 2, 2.0, 1.0) == 2 && losing.exact_step_seconds() == 1.0);
    const unsigned int first = losing.stretch_length();
    std::cout << "  then a stretch of " << first << " exact steps" << std::endl;
    tests::check("  its steps run exact, then own steps again",
                 feed(losing, first, 2.0, 1.0) == first && !losing.runs_exact() && losing.fallbacks() == 1);
    tests::check("  which lose more than an exact step after 2 steps", feed(losing, 2, 2.0, 1.0) == 0 &&
                                                                         losing.runs_exact());
    std::cout << "  a stretch of " << losing.stretch_length() << " (at least twice the last, at most "
              << fem::ExactFallback::longest_stretch << ")" << std::endl;

    fem::ExactFallback mild;
    mild.set_exact_estimate(0.5);
    feed(mild, 6, 1.25, 1.0);
    std::cout << "  own steps that lose by 25 %: a stretch of " << mild.stretch_length() << std::endl;
    tests::check("  own steps that win (0.5) after it stay: 96 steps, none exact",
                 feed(mild, mild.stretch_length(), 1.25, 1.0) == mild.stretch_length() &&
                   feed(mild, 96, 0.5, 1.0) == 0);
    feed(mild, 8, 1.25, 1.0);
    std::cout << "  a loss after a win: a stretch of " << mild.stretch_length() << " again (not doubled)"
              << std::endl;
    fem::ExactFallback small;
    small.set_exact_estimate(0.5);
    feed(small, 6, 1.05, 1.0);
    std::cout << "  own steps that lose by 5 % (a window of 8 to tell): a stretch of " << small.stretch_length()
              << std::endl;

    fem::ExactFallback clearly_paying;
    clearly_paying.set_exact_estimate(0.5);
    tests::check("  own steps under half the estimate: 200 steps, none exact",
                 feed(clearly_paying, 200, 0.2, 1.0) == 0 && clearly_paying.fallbacks() == 0);
    fem::ExactFallback paying;
    paying.set_exact_estimate(0.5);
    tests::check("  own steps cheaper than the estimate, not half of it: a probe measures the exact step, "
                 "then none in 200 steps",
                 feed(paying, 200, 0.4, 1.0) == fem::ExactFallback::probe && paying.exact_step_seconds() == 1.0 &&
                   paying.fallbacks() == 0);
    fem::ExactFallback held_up;
    held_up.set_exact_estimate(0.5);
    feed(held_up, 10, 0.1, 1.0);
    tests::check("  one own step held up (as long as 4 exact ones) among own steps that pay: no stretch",
                 feed(held_up, 1, 2.0, 1.0) == 0 && feed(held_up, 100, 0.1, 1.0) <= fem::ExactFallback::probe &&
                   held_up.fallbacks() == 0);

    // An incision: own steps that refresh a cut's columns cost more than half the estimate
    // (a probe, if they were weighed), among own steps that pay. The exact path's
    // factorization absorbs a cut for nothing, and the cut's chooser took the cheapest
    // refresh: those steps are not weighed.
    const auto incision = [](const bool paid_for_a_change) {
      fem::ExactFallback fallback;
      fallback.set_exact_estimate(0.5);
      const unsigned int before = feed(fallback, 10, 0.2, 1.0);
      const unsigned int during = feed(fallback, 18, 0.8, 1.0, nullptr, paid_for_a_change);
      return before + during + feed(fallback, 100, 0.2, 1.0);
    };
    tests::check("  18 own steps that refresh a cut's columns (0.8) among own steps at 0.2: none exact",
                 incision(true) == 0);
    const unsigned int weighed = incision(false);
    std::cout << "  the same steps weighed as the strategy's own: " << weighed << " exact (probes)" << std::endl;
    tests::check("  at least a probe", weighed >= fem::ExactFallback::probe);

    // Own steps of a stale factor spread widely (cheap ones, a dear one): a window is
    // judged with the one before it, and against the standard error of their mean.
    fem::ExactFallback dear_window;
    dear_window.set_exact_estimate(0.5);
    feed(dear_window, 6, 0.8, 1.0);  // the probe (steps 5, 6) measures 1.0
    feed(dear_window, 16, 0.8, 1.0); // two windows that win
    tests::check("  own steps at 0.8, then a window of eight at 1.08: no stretch (with the window before, they win)",
                 feed(dear_window, 8, 1.08, 1.0) == 0 && !dear_window.runs_exact());
    tests::check("  a second window at 1.08: a stretch",
                 feed(dear_window, 8, 1.08, 1.0) == 0 && dear_window.runs_exact() && dear_window.fallbacks() == 1);
    fem::ExactFallback wide_loss;
    wide_loss.set_exact_estimate(0.5);
    feed(wide_loss, 6, 0.8, 1.0);  // the probe measures 1.0
    feed(wide_loss, 16, 0.8, 1.0); // two windows that win
    unsigned int own_steps = 0;
    for (; own_steps < 100 && wide_loss.fallbacks() == 0; ++own_steps)
      feed(wide_loss, 1, own_steps % 2 == 0 ? 0.85 : 1.25, 1.0);
    std::cout << "  own steps that lose by 5 % within their spread (0.85 and 1.25 in turn): a stretch after "
              << own_steps << " steps" << std::endl;
    tests::check("  after more than a window, within the longest window and the one before it",
                 own_steps > fem::ExactFallback::window &&
                   own_steps <= fem::ExactFallback::longest_window + fem::ExactFallback::window);

    // A retry whose step gave up its solve for an exact step: another stretch at once.
    fem::ExactFallback failing;
    failing.set_exact_estimate(0.5);
    feed(failing, 6, 1.25, 1.0);
    feed(failing, failing.stretch_length(), 1.25, 1.0);
    const unsigned int first_stretch = failing.stretch_length();
    failing.record_step(1.9, true);
    tests::check("  a retry whose first step gave up its solve: a stretch again at once, twice as long",
                 failing.runs_exact() && failing.fallbacks() == 2 && failing.stretch_length() == 2 * first_stretch);
    fem::ExactFallback tie;
    tie.set_exact_estimate(0.5);
    // A probe once the estimate is lost (steps 5, 6), then after 16, 32 and 64 own steps.
    tests::check("  a tie within the margin (own 1.015x exact): probes at doubling intervals only",
                 feed(tie, 130, 1.015, 1.0) == 4 * fem::ExactFallback::probe && tie.fallbacks() == 0);

    // The probe ran on a slow stretch of the machine (its exact steps 1.2, not 1.0): the own
    // steps (1.1) seem to win; the next probe, 24 own steps later (3 windows: the interval
    // whose probe costs 1 %, 19 steps), measures 1.0.
    fem::ExactFallback misled;
    misled.set_exact_estimate(0.5);
    feed(misled, 12, 1.1, 1.2);
    const unsigned int misled_exact = misled.exact_steps();
    tests::check("  a probe measured on a slow stretch: measured again and a stretch within 30 steps",
                 misled_exact == fem::ExactFallback::probe && misled.fallbacks() == 0 &&
                   feed(misled, 30, 1.1, 1.0) > fem::ExactFallback::probe && misled.fallbacks() == 1);
    // The converse: own steps (0.6) win against a measured exact step (1.0), then the
    // machine slows down by half; a window of own steps at 1.2 loses to the 1.0 measured
    // before, and a stretch starts whose first window of exact steps costs 2.0: a slow
    // spell, not a loss, and the own steps come back.
    fem::ExactFallback slow_spell;
    slow_spell.set_exact_estimate(0.5);
    feed(slow_spell, 30, 0.6, 1.0);
    unsigned int slow_steps = 0;
    for (; slow_steps < 40 && !slow_spell.runs_exact(); ++slow_steps)
      feed(slow_spell, 1, 1.2, 2.0);
    const unsigned int slow_stretch = slow_spell.stretch_length();
    tests::check("  a slow spell of the machine: a stretch, which ends after its first window",
                 slow_spell.fallbacks() == 1 && slow_stretch > fem::ExactFallback::window &&
                   feed(slow_spell, fem::ExactFallback::window, 1.2, 2.0) == fem::ExactFallback::window &&
                   !slow_spell.runs_exact() && slow_spell.stretches_ended() == 1);
    tests::check("  the own steps go on once it is over: 100 steps, no stretch",
                 feed(slow_spell, 100, 0.6, 1.0) <= fem::ExactFallback::probe && slow_spell.fallbacks() == 1);
    tests::check("  a stretch after a real loss runs its length",
                 losing.stretches_ended() == 0 && mild.stretches_ended() == 0);

    fem::ExactFallback winning;
    winning.set_exact_estimate(0.5);
    feed(winning, 6, 1.0, 2.0); // the probe: steps 5, 6
    tests::check("  own steps at half an exact step after a probe: the next probe 200 steps later",
                 feed(winning, 199, 1.0, 2.0) == 0 && feed(winning, 10, 1.0, 2.0) == fem::ExactFallback::probe);

    // The price of never losing: own steps that lose by 30 % throughout, against the exact
    // path on every step.
    for (const unsigned int steps : {100u, 1000u, 10000u})
      {
        fem::ExactFallback long_run;
        long_run.set_exact_estimate(0.5);
        double             total = 0;
        const unsigned int exact = feed(long_run, steps, 1.3, 1.0, &total);
        std::cout << "  own steps at 1.3x exact, " << steps << " steps: " << exact << " exact, "
                  << long_run.fallbacks() << " stretch(es)" << std::endl;
        // The two losing steps that detect the loss weigh 0.6 % of the shortest run.
        tests::check_below("    the run's cost over the exact path's - 1", total / steps - 1, steps < 1000 ? 0.02 : 0.01);
      }
  }

  struct Run
  {
    std::vector<fem::Vector3> positions;
    unsigned int              exact_steps = 0, fallbacks = 0;
    /** Steps that ran exact, whoever chose them (auto's own or its fall-back). */
    unsigned int exact_choices = 0;
    /**
     * The fall-back's steps whose stages were not the reference's, those that estimated
     * errors; the own steps right after a stretch.
     */
    unsigned int other_stages = 0, estimated = 0, retries = 0;
  };

  /** The stages of one step of @p statistics, sorted: what the step ran, not in which order. */
  std::vector<std::string> stage_names(const fem::StepStatistics &statistics)
  {
    std::vector<std::string> names;
    for (const auto &stage : statistics.stages.stages())
      names.push_back(stage.name);
    std::sort(names.begin(), names.end());
    return names;
  }

  Run run(const std::string &name, const std::string &scene_text, const unsigned int steps,
          const std::vector<std::string> &reference_stages = {})
  {
    tests::write_file(name, scene_text);
    app::Scene scene{app::AllParameters(name)};
    const auto *wcc = dynamic_cast<const fem::WarpCancelingModel *>(&scene.model());
    Run         result;
    bool        last_fell_back = false;
    for (unsigned int step = 0; step < steps; ++step)
      {
        fem::StepStatistics statistics;
        scene.integrator().advance(statistics);
        result.exact_choices +=
          statistics.choice == fem::StepChoice::exact || statistics.choice == fem::StepChoice::fallback;
        // The fall-back records a step when the next one is prepared: until then it still
        // says what this one was.
        const bool fell_back = wcc && wcc->exact_fallback().runs_exact();
        if (fell_back)
          {
            result.other_stages += statistics.choice != fem::StepChoice::fallback;
            result.estimated += statistics.stages.ran(fem::stage::error_estimate);
            result.other_stages += stage_names(statistics) != reference_stages;
          }
        if (last_fell_back && !fell_back)
          ++result.retries;
        last_fell_back = fell_back;
      }
    result.positions = scene.integrator().positions();
    if (wcc)
      {
        result.exact_steps = wcc->exact_fallback().exact_steps();
        result.fallbacks   = wcc->exact_fallback().fallbacks();
      }
    return result;
  }
} // namespace

int main()
{
  given_costs();

  std::cout << "on scenes:" << std::endl;
  // Longer than the longest stretch: the own steps get at least one window after one.
  const unsigned int steps = fem::ExactFallback::longest_stretch + 76;
  // The exact path's step: its stages.
  std::vector<std::string> corotational_stages;
  {
    tests::write_file("corotational.prm", tests::small_torus_scene("  set Type = corotational\n"));
    app::Scene          scene{app::AllParameters("corotational.prm")};
    fem::StepStatistics statistics;
    scene.integrator().advance(statistics);
    corotational_stages = stage_names(statistics);
  }
  std::cout << "  the exact path's step:";
  for (const auto &name : corotational_stages)
    std::cout << " " << name << ";";
  std::cout << std::endl;

  const Run exact  = run("exact.prm",
                        tests::small_torus_scene("  set Type = warp_canceling\n"
                                                 "  set Rerotation threshold = 0\n"),
                        steps);
  const Run losing = run("losing.prm",
                         tests::small_torus_scene("  set Type = warp_canceling\n"
                                                  "  set Strategy = auto\n"
                                                  "  set Rerotation threshold = 1e-12\n"
                                                  "  set CG tolerance = 1e-10\n"),
                         steps, corotational_stages);
  tests::check("  where nothing pays, auto runs exact steps on most steps", losing.exact_choices >= steps / 2);
  tests::check("  and falls back", losing.fallbacks >= 1 && losing.exact_steps >= steps / 4);
  tests::check("  a step of the fall-back runs the exact path's stages, no more", losing.other_stages == 0);
  tests::check("  none estimates errors", losing.estimated == 0);
  tests::check("  its own steps come back after a stretch", losing.retries >= 1);
  const Run at_rest = run("rest.prm", tests::small_torus_scene("  set Type = warp_canceling\n"), 0);
  tests::check_below("  its trajectory against the exact path's (relative to the motion)",
                     tests::relative_difference(losing.positions, exact.positions, at_rest.positions), 1e-3);

  const Run paying = run("paying.prm",
                         "subsection Mesh\n"
                         "  set Source = file\n"
                         "  set File   = " SOURCE_DIR "/../meshes/torus_fine.msh\n"
                         "end\n" +
                           tests::without_subsection(tests::small_torus_scene("  set Type = warp_canceling\n"
                                                                              "  set Strategy = auto\n"
                                                                              "  set Rerotation threshold = inf\n"),
                                                     "Mesh"),
                         30);
  // Under the sanitizers the error estimate, the element pass and CG (the project's code,
  // instrumented) cost several times more against the factorization (BLAS, not
  // instrumented): there own steps need not pay, and the decision is not checked.
  tests::check("  where its own steps pay, it does not fall back", paying.exact_steps == 0 || tests::sanitized);
}
