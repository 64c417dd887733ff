#include <warpchol/models/forecast_solver_control.h>

#include <algorithm>
#include <cmath>

namespace warpchol::fem
{
  ForecastSolverControl::ForecastSolverControl(const unsigned int limit, const double tolerance)
    : dealii::SolverControl(limit, tolerance, false, false)
  {}

  dealii::SolverControl::State ForecastSolverControl::check(const unsigned int step, const double check_value)
  {
    if (step == 0)
      {
        residuals.clear();
        forecast_failure = false;
      }
    residuals.push_back(check_value);
    const State state = dealii::SolverControl::check(step, check_value);
    // No forecast without a tolerance to reach, or without the iterations it reads.
    if (state != iterate || step < first_forecast || step + 1 != residuals.size() || !(tolerance() > 0))
      return state;
    const unsigned int recent = std::max(4u, step / 2);
    const double       rate   = std::pow(check_value / residuals[step - recent], 1. / recent);
    const double       needed = rate < 1 ? std::log(tolerance() / check_value) / std::log(rate) : INFINITY;
    if (step + needed <= max_steps())
      return state;
    forecast_failure = true;
    lcheck           = failure;
    return failure;
  }

  bool ForecastSolverControl::gave_up_on_forecast() const
  {
    return forecast_failure;
  }
} // namespace warpchol::fem
