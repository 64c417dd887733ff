#include <warpchol/app/trajectory_error.h>

#include <algorithm>
#include <cmath>

namespace warpchol::app
{
  PositionError position_error(const std::vector<fem::Vector3> &positions,
                               const std::vector<fem::Vector3> &reference,
                               const std::vector<fem::Vector3> &rest)
  {
    double largest_difference = 0, sum_of_squares = 0, motion = 0;
    for (unsigned int v = 0; v < positions.size(); ++v)
      {
        const double difference = (positions[v] - reference[v]).norm();
        largest_difference      = std::max(largest_difference, difference);
        sum_of_squares += difference * difference;
        motion = std::max(motion, (reference[v] - rest[v]).norm());
      }
    const double  scale = motion > 0 ? motion : 1;
    PositionError error;
    error.max = largest_difference / scale;
    error.rms = positions.empty() ? 0 : std::sqrt(sum_of_squares / positions.size()) / scale;
    return error;
  }

  void TrajectoryError::add(const PositionError &step_error)
  {
    ++steps;
    largest.max = std::max(largest.max, step_error.max);
    largest.rms = std::max(largest.rms, step_error.rms);
    sum.max += step_error.max;
    sum.rms += step_error.rms;
    last = step_error;
  }

  unsigned int TrajectoryError::n_steps() const
  {
    return steps;
  }

  double TrajectoryError::max_error() const
  {
    return largest.max;
  }

  double TrajectoryError::mean_error() const
  {
    return steps > 0 ? sum.max / steps : 0;
  }

  double TrajectoryError::last_error() const
  {
    return last.max;
  }

  double TrajectoryError::max_rms_error() const
  {
    return largest.rms;
  }

  double TrajectoryError::mean_rms_error() const
  {
    return steps > 0 ? sum.rms / steps : 0;
  }
} // namespace warpchol::app
