// ForecastSolverControl: CG stopped as soon as its recent rate of convergence forecasts the
// tolerance past the limit, and not otherwise. On residual sequences fed to check(): a
// steady fast fall converges; a slow fall (a tenth of the way in the limit) fails at the
// first forecast; a slow start that speeds up before it (CG's shape on a stale
// preconditioner) is not stopped. With deal.II's CG on a diagonal system of condition 10:
// with a limit of 100 the forecast lets the solve run to the same iterations and solution
// as the plain control; with a limit it cannot make, both fail, the forecast earlier.

#include <warpchol/models/forecast_solver_control.h>

#include <deal.II/lac/diagonal_matrix.h>
#include <deal.II/lac/precondition.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/vector.h>

#include <cmath>
#include <vector>

#include "tests.h"

using namespace warpchol;
using dealii::SolverControl;

namespace
{
  /** Feeds @p residuals to @p control until it stops; the step it stopped at and its state. */
  std::pair<unsigned int, SolverControl::State> run(SolverControl &control, const std::vector<double> &residuals)
  {
    for (unsigned int k = 0; k < residuals.size(); ++k)
      {
        const SolverControl::State state = control.check(k, residuals[k]);
        if (state != SolverControl::iterate)
          return {k, state};
      }
    return {static_cast<unsigned int>(residuals.size()), SolverControl::iterate};
  }

  std::vector<double> geometric(const double start, const double rate, const unsigned int n)
  {
    std::vector<double> r(n);
    for (unsigned int k = 0; k < n; ++k)
      r[k] = start * std::pow(rate, k);
    return r;
  }
} // namespace

int main()
{
  {
    fem::ForecastSolverControl control(30, 1e-8);
    const auto [step, state] = run(control, geometric(1., 0.3, 40));
    std::cout << "rate 0.3 to 1e-8 in a limit of 30: stopped at " << step << ", "
              << (state == SolverControl::success ? "converged" : "failed") << std::endl;
    tests::check("  not on the forecast", !control.gave_up_on_forecast());
  }
  {
    fem::ForecastSolverControl control(30, 1e-8);
    const auto [step, state] = run(control, geometric(1., 0.9, 40));
    std::cout << "rate 0.9 (175 iterations to 1e-8) in a limit of 30: stopped at " << step << ", "
              << (state == SolverControl::failure ? "failed" : "not failed") << std::endl;
    tests::check("  on the forecast, at its first", control.gave_up_on_forecast() &&
                                                        step == fem::ForecastSolverControl::first_forecast);
  }
  {
    // Three iterations at a rate of 0.9, then 0.2: 15 in all.
    std::vector<double> residuals = geometric(1., 0.9, 4);
    for (unsigned int k = 1; residuals.back() > 1e-9; ++k)
      residuals.push_back(residuals[3] * std::pow(0.2, k));
    fem::ForecastSolverControl control(30, 1e-8);
    const auto [step, state] = run(control, residuals);
    std::cout << "three iterations at a rate of 0.9, then 0.2, in a limit of 30: stopped at " << step << ", "
              << (state == SolverControl::success ? "converged" : "failed") << std::endl;
    tests::check("  converged, not stopped on the slow start", state == SolverControl::success);
  }
  {
    const unsigned int     n = 400;
    dealii::Vector<double> diagonal(n), b(n);
    for (unsigned int i = 0; i < n; ++i)
      {
        diagonal[i] = std::pow(10., static_cast<double>(i) / (n - 1));
        b[i]        = 1.;
      }
    dealii::DiagonalMatrix<dealii::Vector<double>> matrix(diagonal);
    const auto solve = [&](SolverControl &control, dealii::Vector<double> &x) {
      x.reinit(n);
      dealii::SolverCG<dealii::Vector<double>> cg(control);
      try
        {
          cg.solve(matrix, x, b, dealii::PreconditionIdentity());
          return true;
        }
      catch (const SolverControl::NoConvergence &)
        {
          return false;
        }
    };
    const double               tolerance = 1e-8 * b.l2_norm();
    SolverControl              plain(100, tolerance, false, false);
    fem::ForecastSolverControl forecast(100, tolerance);
    dealii::Vector<double>     x_plain, x_forecast;
    const bool                 plain_converged    = solve(plain, x_plain);
    const bool                 forecast_converged = solve(forecast, x_forecast);
    x_forecast -= x_plain;
    std::cout << "CG, condition 10, limit 100: plain " << plain.last_step() << " iterations, forecast "
              << forecast.last_step() << std::endl;
    tests::check("  both converge, in the same iterations, to the same bits",
                 plain_converged && forecast_converged && plain.last_step() == forecast.last_step() &&
                   x_forecast.linfty_norm() == 0);

    SolverControl              plain_short(20, tolerance, false, false);
    fem::ForecastSolverControl forecast_short(20, tolerance);
    const bool plain_failed = !solve(plain_short, x_plain), forecast_failed = !solve(forecast_short, x_forecast);
    std::cout << "the same, limit 20: plain fails after " << plain_short.last_step() << ", forecast after "
              << forecast_short.last_step() << std::endl;
    tests::check("  both fail, the forecast earlier", plain_failed && forecast_failed &&
                                                          forecast_short.gave_up_on_forecast() &&
                                                          forecast_short.last_step() < plain_short.last_step());
  }
}
