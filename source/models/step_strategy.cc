#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/models/step_strategy.h>

#include <algorithm>
#include <cmath>

namespace warpchol::fem
{
  bool StepStrategy::iterates() const
  {
    return kind != Kind::partial;
  }

  std::string to_string(const StepStrategy::Kind kind)
  {
    return name_of(step_strategy_names, kind);
  }

  StepStrategy::Kind parse_step_strategy(const std::string &name)
  {
    return parse_name(step_strategy_names, name, "step strategy");
  }

  std::string to_string(const StepStrategy::Target target)
  {
    return name_of(iteration_target_names, target);
  }

  StepStrategy::Target parse_iteration_target(const std::string &name)
  {
    return parse_name(iteration_target_names, name, "iteration target");
  }

  std::string to_string(const cholesky::Refresh refresh)
  {
    switch (refresh)
      {
        case cholesky::Refresh::all:
          return "all";
        case cholesky::Refresh::below_top:
          return "below_top";
        case cholesky::Refresh::none:
          return "none";
      }
    return "unknown";
  }

  namespace
  {
    /** Weight of a new measurement in the moving averages. */
    constexpr double smoothing = 0.3;

    void blend(double &average, const double value)
    {
      average = average > 0 ? (1 - smoothing) * average + smoothing * value : value;
    }

    /** blend() for a time: noise only adds time, so one under half the average replaces it. */
    void blend_seconds(double &average, const double value)
    {
      if (value < 0.5 * average)
        average = value;
      else
        blend(average, value);
    }
  } // namespace

  void StepCostModel::record_iterations(const cholesky::Refresh refresh, const unsigned int iterations,
                                        const double seconds)
  {
    if (iterations > 0)
      blend_seconds(seconds_per_iteration, seconds / iterations);
    if (refresh == cholesky::Refresh::all)
      blend(iterations_after_all, iterations);
    else if (refresh == cholesky::Refresh::below_top)
      {
        if (iterations_after_top < 0)
          iterations_after_top = iterations;
        else
          blend(iterations_after_top, iterations);
      }
    last_iterations = iterations;
  }

  void StepCostModel::record_exact_step(const double seconds, const unsigned int cycle_length)
  {
    blend_seconds(exact_seconds, seconds);
    // The steps past the cycle's end were not seen this time: what was measured there may
    // be old (a step after a cut iterates more). Relax it toward the last one seen, so that
    // a later cycle goes further and measures it again.
    const unsigned int last = std::min(cycle_length, longest_staleness);
    if (last == 0 || iterations_at[last - 1] < 0)
      return;
    for (unsigned int s = last + 1; s <= longest_staleness; ++s)
      if (iterations_at[s - 1] > iterations_at[last - 1])
        blend(iterations_at[s - 1], iterations_at[last - 1]);
  }

  void StepCostModel::record_iterating_step(const unsigned int staleness, const double seconds,
                                            const unsigned int iterations)
  {
    if (staleness == 0)
      return;
    record_iterations_at(staleness, iterations);
    if (seconds_per_iteration > 0)
      blend_seconds(iterating_overhead, std::max(seconds - iterations * seconds_per_iteration, 1e-9));
  }

  void StepCostModel::record_iterations_at(const unsigned int staleness, const unsigned int iterations)
  {
    if (staleness > 0)
      blend(iterations_at[std::min(staleness, longest_staleness) - 1], iterations);
  }

  void StepCostModel::record_own_step(const bool exact)
  {
    if (exact)
      ++exact_steps_in_a_row;
    else
      {
        if (exact_steps_in_a_row >= iterating_probe_interval)
          iterating_probe_interval = std::min(2 * iterating_probe_interval, longest_probe_interval);
        exact_steps_in_a_row = 0;
      }
  }

  void StepCostModel::record_setup(const double step_seconds, const double factorization_seconds)
  {
    setup_exact_seconds = step_seconds;
    setup_factorization = factorization_seconds;
  }

  double StepCostModel::setup_factorization_seconds() const
  {
    return setup_factorization;
  }

  bool StepCostModel::calibrated(const cholesky::RefactorizationCostModel &factorization_rates) const
  {
    return factorization_rates.knows_factorization_rate() && seconds_per_iteration > 0;
  }

  double StepCostModel::predicted_exact_seconds() const
  {
    return exact_seconds > 0 ? exact_seconds : setup_exact_seconds;
  }

  unsigned int StepCostModel::affordable_iterations() const
  {
    const double exact = predicted_exact_seconds();
    if (!(exact > 0) || !(seconds_per_iteration > 0))
      return 0;
    return static_cast<unsigned int>(std::min(1e6, std::ceil(exact / seconds_per_iteration)));
  }

  double StepCostModel::predicted_iterating_seconds(const unsigned int staleness) const
  {
    if (iterating_overhead < 0 || !(seconds_per_iteration > 0))
      return -1;
    // The last staleness measured at or before this one stands for it.
    for (unsigned int s = std::min(std::max(staleness, 1u), longest_staleness); s >= 1; --s)
      if (iterations_at[s - 1] >= 0)
        return iterating_overhead + iterations_at[s - 1] * seconds_per_iteration;
    return -1;
  }

  bool StepCostModel::exact_step_is_due(const unsigned int staleness, const unsigned int steps_left) const
  {
    const double exact = predicted_exact_seconds();
    if (exact < 0)
      return true;
    if (predicted_iterating_seconds(staleness) < 0)
      return false;
    if (staleness == 1 && exact_steps_in_a_row >= iterating_probe_interval)
      return false;
    // The rule holds for costs that do not fall with the staleness; the measured ones may
    // (a step right after an exact one that needed an iteration more than its successors):
    // the rule reads their running maximum, or it could refresh forever.
    std::vector<double> cost(longest_staleness, 0.);
    double              largest = 0;
    for (unsigned int s = 1; s <= longest_staleness; ++s)
      cost[s - 1] = largest = std::max(largest, std::max(predicted_iterating_seconds(s), 0.));
    // The least average cost of a cycle that starts with an exact step.
    double cycle = exact, least_average = exact;
    for (unsigned int length = 2; length <= longest_staleness; ++length)
      {
        cycle += cost[length - 2];
        least_average = std::min(least_average, cycle / length);
      }
    const auto cost_at = [&](const unsigned int s) { return cost[std::min(std::max(s, 1u), longest_staleness) - 1]; };
    if (cost_at(staleness) <= least_average)
      return false;
    if (steps_left == 0)
      return true;
    // Near the run's end a cycle cannot run its course: an exact step now, then the steps
    // after it, against iterating on at the staleness reached.
    double exact_now = exact, iterate_on = 0;
    for (unsigned int k = 0; k < steps_left; ++k)
      {
        exact_now += k > 0 ? cost_at(k) : 0.;
        iterate_on += cost_at(staleness + k);
      }
    return exact_now < iterate_on;
  }

  void StepCostModel::save(BinaryWriter &writer) const
  {
    for (const double value : {setup_factorization, seconds_per_iteration, iterations_after_all, iterations_after_top,
                               last_iterations, exact_seconds, setup_exact_seconds, iterating_overhead})
      writer.write(value);
    writer.write(iterations_at);
    writer.write(exact_steps_in_a_row);
    writer.write(iterating_probe_interval);
  }

  void StepCostModel::load(BinaryReader &reader)
  {
    for (double *value : {&setup_factorization, &seconds_per_iteration, &iterations_after_all, &iterations_after_top,
                          &last_iterations, &exact_seconds, &setup_exact_seconds, &iterating_overhead})
      reader.read(*value);
    reader.read(iterations_at);
    if (iterations_at.size() != longest_staleness)
      reader.fail("the cost model's step costs have the wrong length (corrupt)");
    reader.read(exact_steps_in_a_row);
    reader.read(iterating_probe_interval);
    if (iterating_probe_interval < shortest_probe_interval || iterating_probe_interval > longest_probe_interval)
      reader.fail("the cost model's probe interval is out of range (corrupt)");
  }

  RefreshPlacement::Where RefreshPlacement::current() const
  {
    return where;
  }

  unsigned int RefreshPlacement::steps_in(const Where place) const
  {
    return counts[static_cast<int>(place)];
  }

  void RefreshPlacement::record_step(const double seconds)
  {
    ++counts[static_cast<int>(where)];
    if (++steps < first_counted_step)
      return;
    phase_seconds += seconds;
    const unsigned int length = trial ? window : stretch;
    if (++phase_steps < length)
      return;
    // The phase is over: its mean is what this place costs now.
    const int here = static_cast<int>(where), other = 1 - here;
    mean_seconds[here] = phase_seconds / phase_steps;
    phase_seconds      = 0;
    phase_steps        = 0;
    if (mean_seconds[other] < 0)
      {
        // The other place was never tried: try it.
        where = static_cast<Where>(other);
        trial = true;
        return;
      }
    if (trial)
      {
        // A trial against the place that ran before: the cheaper runs the next stretch,
        // longer if the trial lost (the incumbent holds), the shortest if it won.
        const bool trial_won = mean_seconds[here] < mean_seconds[other];
        stretch              = trial_won ? shortest_stretch : std::min(2 * stretch, longest_stretch);
        where                = static_cast<Where>(trial_won ? here : other);
        trial                = false;
        return;
      }
    // A stretch is over: try the other place again.
    where = static_cast<Where>(other);
    trial = true;
  }

  void RefreshPlacement::save(BinaryWriter &writer) const
  {
    writer.write(static_cast<int>(where));
    writer.write(steps);
    writer.write(phase_steps);
    writer.write(phase_seconds);
    writer.write(trial);
    writer.write(stretch);
    for (const double mean : mean_seconds)
      writer.write(mean);
    for (const unsigned int count : counts)
      writer.write(count);
  }

  void RefreshPlacement::load(BinaryReader &reader)
  {
    const int place = reader.get<int>();
    if (place != 0 && place != 1)
      reader.fail("the refresh placement is neither 0 nor 1 (corrupt)");
    where = static_cast<Where>(place);
    reader.read(steps);
    reader.read(phase_steps);
    reader.read(phase_seconds);
    reader.read(trial);
    reader.read(stretch);
    for (double &mean : mean_seconds)
      reader.read(mean);
    for (unsigned int &count : counts)
      reader.read(count);
  }

  double StepCostModel::predicted_seconds(const cholesky::Refresh refresh, const double refresh_seconds) const
  {
    double iterations = last_iterations + 1;
    if (refresh == cholesky::Refresh::all)
      iterations = iterations_after_all;
    else if (refresh == cholesky::Refresh::below_top)
      // Not tried yet: assume a little worse than a full refresh, so that it gets tried.
      iterations = iterations_after_top >= 0 ? iterations_after_top : iterations_after_all + 1;
    return refresh_seconds + iterations * seconds_per_iteration;
  }
  bool ExactFallback::runs_exact() const
  {
    return exact;
  }

  void ExactFallback::set_exact_estimate(const double seconds)
  {
    estimate = seconds;
  }

  double ExactFallback::exact_step_seconds() const
  {
    return exact_seconds;
  }

  double ExactFallback::own_step_seconds() const
  {
    return own_seconds;
  }

  unsigned int ExactFallback::stretch_length() const
  {
    return stretch;
  }

  unsigned int ExactFallback::exact_steps() const
  {
    return exact_count;
  }

  unsigned int ExactFallback::fallbacks() const
  {
    return fallback_count;
  }

  unsigned int ExactFallback::stretches_ended() const
  {
    return stretches_ended_early;
  }

  bool ExactFallback::own_steps_lose(const double seconds, const double error, const double reference) const
  {
    return reference > 0 && seconds - error > (1 + margin) * reference;
  }

  void ExactFallback::start_stretch()
  {
    // Own steps that lose by the share `loss` of an exact step end their next window
    // after retry_steps of them (the window, or the CUSUM passing one exact step: 1 /
    // (loss - margin) steps), which cost retry_steps * loss exact steps more than the
    // exact path: the stretch that makes that retry_budget of its time, or longer.
    const double loss        = own_seconds / exact_seconds - 1;
    const double retry_steps = loss > margin ? std::min<double>(window, std::ceil(1 / (loss - margin))) : window;
    double       length      = std::max<double>(shortest_stretch, std::ceil(retry_steps * loss / retry_budget));
    if (after_stretch)
      length = std::max<double>(length, 2. * stretch);
    stretch       = static_cast<unsigned int>(std::min<double>(length, longest_stretch));
    phase_length  = stretch;
    // The stretch measures the exact path anew: no probe is due after it.
    probe_interval        = 0;
    own_steps_since_probe = 0;
    after_stretch = false;
    // The own steps after it are judged on their own.
    earlier_steps   = 0;
    earlier_seconds = 0;
    earlier_squares = 0;
    ++fallback_count;
  }

  void ExactFallback::schedule_probe()
  {
    // A probe while the own steps win costs probe (exact / own - 1) own steps: the
    // interval that makes that retry_budget of its time, at least twice the last one, so
    // that a reference measured on a slow stretch of the machine is measured again soon,
    // and one that keeps holding costs ever less.
    const double cost   = own_seconds > 0 ? probe * std::max(0., exact_seconds / own_seconds - 1) : 0.;
    const double length = std::max<double>({shortest_stretch, 2. * probe_interval, std::ceil(cost / retry_budget)});
    probe_interval        = static_cast<unsigned int>(std::min<double>(length, longest_stretch));
    own_steps_since_probe = 0;
  }

  void ExactFallback::record_step(const double seconds, const bool solve_failed, const bool paid_for_a_change)
  {
    const bool step_was_exact = exact;
    if (step_was_exact)
      ++exact_count;
    if (++steps < first_counted_step || (paid_for_a_change && !step_was_exact))
      return;
    phase_seconds += seconds;
    phase_squares += seconds * seconds;
    ++phase_steps;
    if (step_was_exact)
      {
        // A window of the stretch that costs as much as the own steps that lost: the
        // machine slowed down, not the strategy; the stretch ends there.
        const bool slow_spell = !probing && phase_steps == window && phase_steps < phase_length &&
                                !own_steps_lose(own_seconds, 0., phase_seconds / phase_steps);
        if (phase_steps < phase_length && !slow_spell)
          return;
        // The run of exact steps is over: its mean is what the exact path costs now.
        exact_seconds = phase_seconds / phase_steps;
        phase_seconds = 0;
        phase_squares = 0;
        phase_steps   = 0;
        if (probing)
          {
            // The probe measured the reference: a stretch if the own steps lose to it, else
            // they go on, and a probe again after a while (schedule_probe()).
            probing = false;
            if (own_steps_lose(own_seconds, own_error, exact_seconds))
              start_stretch();
            else
              {
                exact = false;
                schedule_probe();
              }
            return;
          }
        // A stretch is over: the strategy's own steps get a window again; after a slow
        // spell as after a win (a later loss starts from its own length).
        exact = false;
        if (slow_spell)
          {
            stretch = 0;
            ++stretches_ended_early;
          }
        else
          after_stretch = true;
        return;
      }
    // What the own steps lost to the exact path since they last did not (a CUSUM): steps
    // far dearer than an exact one end the window at once. Two of them: one step held up
    // by something else on the machine is not the strategy's cost.
    const bool   measured  = exact_seconds > 0;
    const double reference = measured ? exact_seconds : estimate;
    if (reference > 0)
      {
        excess = std::max(0., excess + seconds - (1 + margin) * reference);
        losing_steps += seconds > (1 + margin) * reference;
      }
    // A retry after a stretch whose step gave up its solve for an exact one has lost more
    // than an exact step by itself, and no machine's hiccup does that: over at once.
    const bool retry_failed       = after_stretch && solve_failed;
    const bool lost_an_exact_step = reference > 0 && ((excess > reference && losing_steps >= 2) || retry_failed);
    if (phase_steps < window && !lost_an_exact_step)
      return;
    // The mean of the window and of the one before it (unless a stretch came between),
    // and its standard error; past longest_window the mean alone decides. A window the
    // CUSUM ended has lost an exact step already: its own steps' mean, nothing to weigh.
    const bool   pooled   = !lost_an_exact_step;
    const double n        = phase_steps + (pooled ? earlier_steps : 0);
    const double mean     = (phase_seconds + (pooled ? earlier_seconds : 0.)) / n;
    const double squares  = phase_squares + (pooled ? earlier_squares : 0.);
    const double variance = n > 1 ? std::max(0., squares - n * mean * mean) / (n - 1) : 0.;
    const double error    = pooled && phase_steps < longest_window ? std::sqrt(variance / n) : 0.;
    // Against an estimate: a probe unless they clearly win, by what it may overstate.
    const bool loses = measured ? own_steps_lose(mean, error, reference) : estimate_doubt * mean > reference;
    // A loss within the window's spread: more steps tell.
    if (measured && !lost_an_exact_step && !loses && own_steps_lose(mean, 0., reference))
      return;
    own_seconds                  = mean;
    own_error                    = error;
    const unsigned int in_window = phase_steps;
    earlier_steps                = phase_steps;
    earlier_seconds              = phase_seconds;
    earlier_squares              = phase_squares;
    phase_seconds                = 0;
    phase_squares                = 0;
    phase_steps                  = 0;
    losing_steps                 = 0;
    bool probe_due               = false;
    if (!lost_an_exact_step && !loses)
      {
        // The own steps won (again): a later fall-back starts from its own loss. The exact
        // path, once measured, is measured again from time to time (schedule_probe()).
        after_stretch = false;
        stretch       = 0;
        if (!measured)
          return;
        if (probe_interval == 0)
          schedule_probe();
        own_steps_since_probe += in_window;
        probe_due = own_steps_since_probe >= probe_interval;
        if (!probe_due)
          return;
      }
    excess = 0;
    exact  = true;
    if (!measured || probe_due)
      {
        probing      = true;
        phase_length = probe;
        return;
      }
    start_stretch();
  }

  void ExactFallback::save(BinaryWriter &writer) const
  {
    writer.write(exact);
    writer.write(steps);
    writer.write(phase_steps);
    writer.write(phase_seconds);
    writer.write(phase_length);
    writer.write(probing);
    writer.write(stretch);
    writer.write(after_stretch);
    writer.write(phase_squares);
    writer.write(earlier_steps);
    writer.write(earlier_seconds);
    writer.write(earlier_squares);
    writer.write(own_seconds);
    writer.write(own_error);
    writer.write(excess);
    writer.write(losing_steps);
    writer.write(exact_seconds);
    writer.write(estimate);
    writer.write(exact_count);
    writer.write(fallback_count);
    writer.write(probe_interval);
    writer.write(own_steps_since_probe);
    writer.write(stretches_ended_early);
  }

  void ExactFallback::load(BinaryReader &reader)
  {
    reader.read(exact);
    reader.read(steps);
    reader.read(phase_steps);
    reader.read(phase_seconds);
    reader.read(phase_length);
    reader.read(probing);
    reader.read(stretch);
    reader.read(after_stretch);
    reader.read(phase_squares);
    reader.read(earlier_steps);
    reader.read(earlier_seconds);
    reader.read(earlier_squares);
    reader.read(own_seconds);
    reader.read(own_error);
    reader.read(excess);
    reader.read(losing_steps);
    reader.read(exact_seconds);
    reader.read(estimate);
    reader.read(exact_count);
    reader.read(fallback_count);
    reader.read(probe_interval);
    reader.read(own_steps_since_probe);
    reader.read(stretches_ended_early);
  }
} // namespace warpchol::fem
