#include <warpchol/base/format.h>
#include <warpchol/models/target_error_controller.h>

#include <algorithm>
#include <bitset>
#include <cmath>

namespace warpchol::fem
{
  namespace
  {
    /** Weight of a new step in the moving averages. */
    constexpr double smoothing = 0.3;
    /** "Far over the goal": this many times it. */
    constexpr double far_over = 4;
    /** The last five steps, one bit each. */
    constexpr unsigned int recent_steps = 0x1f;
  } // namespace

  TargetErrorController::TargetErrorController(const double target, const double threshold)
    : target_error(target)
    , start_threshold(threshold)
    , adapted_threshold(threshold)
  {}

  double TargetErrorController::target() const
  {
    return target_error;
  }

  double TargetErrorController::threshold() const
  {
    return adapted_threshold;
  }

  bool TargetErrorController::steering() const
  {
    return target_error > 0 && given_up.empty();
  }

  const std::string &TargetErrorController::why_given_up() const
  {
    return given_up;
  }

  bool TargetErrorController::steer(const unsigned int step, const double last_error, const double rerotated_fraction)
  {
    const double goal   = target_error / 2;
    const double factor = last_error > 0 ? std::clamp(std::pow(goal / last_error, 0.7), 0.125, 2.0) : 2.0;
    adapted_threshold   = std::clamp(adapted_threshold * factor, 1e-6, 100.0);
    recent_rerotated_fraction = (1 - smoothing) * recent_rerotated_fraction + smoothing * rerotated_fraction;
    recent_error_ratio     = (1 - smoothing) * recent_error_ratio + smoothing * last_error / goal;
    far_over_goal          = (far_over_goal << 1 | (last_error > far_over * goal)) & recent_steps;
    const int far_over_steps = static_cast<int>(std::bitset<5>(far_over_goal).count());

    std::string why;
    if (adapted_threshold < start_threshold / 100 && recent_rerotated_fraction > 0.25 && recent_error_ratio > 1)
      why = "the threshold " + format_number(adapted_threshold, 2) + " re-rotates " +
            format_number(100 * recent_rerotated_fraction, 2) + " % of the elements per step and the step error is still " +
            format_number(recent_error_ratio, 2) + " times the goal";
    else if (far_over_steps >= 3)
      why = "the step error was more than " + format_number(far_over) + " times the goal in " +
            std::to_string(far_over_steps) + " of the last 5 steps (the threshold now " +
            format_number(adapted_threshold, 2) + ")";
    else if (recent_rerotated_fraction > 0.4)
      why = "the threshold " + format_number(adapted_threshold, 2) + " holds the step error near the goal only by updating " +
            format_number(100 * recent_rerotated_fraction, 2) + " % of the elements per step, which costs about a full factorization";
    if (why.empty())
      return false;
    given_up = "target error " + format_number(target_error) + " given up at step " + std::to_string(step) + ": " + why +
               "; the steps iterate on the corotational matrix (preconditioned)";
    return true;
  }
} // namespace warpchol::fem
