#pragma once

#include <deal.II/lac/solver_control.h>

#include <vector>

/**
 * @file
 * A SolverControl that gives up on CG as soon as its convergence forecasts a failure.
 */
namespace warpchol::fem
{
  /**
   * deal.II's SolverControl (a limit of iterations, an absolute tolerance), which also
   * gives up, as a failure, once the residual's recent rate of decrease forecasts the
   * tolerance past the limit.
   *
   * Where the limit is what an exact step costs (auto, StepCostModel::affordable_iterations()),
   * a solve that reaches it pays for an exact step in iterations and then for the exact step
   * itself. On a factor that has grown a poor preconditioner the residual falls by a few
   * per cent an iteration from the start: the forecast stops such a solve after a few
   * iterations instead of the limit's.
   *
   * The forecast, from iteration first_forecast onwards: the rate of the last max(4, k/2) of
   * the k iterations so far, rho = (r_k / r_{k-w})^(1/w), continued until the tolerance,
   * k + log(tolerance / r_k) / log(rho) iterations (infinitely many if the residual did not
   * fall). CG's residual falls unevenly, fastest near the end: the recent rate, not the
   * first iterations', and only a forecast past the limit stops it.
   */
  class ForecastSolverControl : public dealii::SolverControl
  {
  public:
    ForecastSolverControl(unsigned int limit, double tolerance);

    State check(unsigned int step, double check_value) override;

    /** Whether the last solve stopped on the forecast (before the limit). */
    bool gave_up_on_forecast() const;

    /** The iteration of the first forecast: a few steps show no rate yet. */
    static constexpr unsigned int first_forecast = 6;

  private:
    std::vector<double> residuals;
    bool                forecast_failure = false;
  };
} // namespace warpchol::fem
