#include <warpchol/base/exceptions.h>
#include <warpchol/contact/friction_cone_solver.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace warpchol::fem
{
  GaussSeidelResult solve_friction_cone(const std::vector<double> &w, const std::vector<double> &free_velocity,
                                        const std::vector<double> &friction, const GaussSeidelSettings &settings,
                                        std::vector<double> &lambda)
  {
    const std::size_t m = free_velocity.size(), n_contacts = m / 3;
    if (m != 3 * n_contacts || friction.size() != n_contacts || w.size() != m * m)
      throw Error("solve_friction_cone(): " + std::to_string(m) + " rows, " + std::to_string(friction.size()) +
                  " friction coefficients, W of " + std::to_string(w.size()) + " entries");
    if (lambda.size() != m)
      lambda.assign(m, 0.);

    // u = free + W lambda, kept up to date as each contact's impulse changes (a column of
    // W per changed row: W is symmetric, its columns contiguous).
    std::vector<double> u = free_velocity;
    const auto          add_column = [&](const std::size_t row, const double delta) {
      if (delta == 0.)
        return;
      const double *column = w.data() + row * m;
      for (std::size_t i = 0; i < m; ++i)
        u[i] += column[i] * delta;
    };
    for (std::size_t row = 0; row < m; ++row)
      add_column(row, lambda[row]);

    GaussSeidelResult result;
    result.converged = n_contacts == 0;
    for (result.iterations = 0; !result.converged && result.iterations < settings.max_iterations;)
      {
        ++result.iterations;
        result.residual = 0;
        for (std::size_t j = 0; j < n_contacts; ++j)
          {
            const std::size_t n = 3 * j, t1 = n + 1, t2 = n + 2;
            const auto        entry = [&](const std::size_t i, const std::size_t k) { return w[i + k * m]; };
            const double      old_n = lambda[n], old_t1 = lambda[t1], old_t2 = lambda[t2];

            // The normal: the impulse that makes u_n vanish, or none if it separates.
            const double new_n = std::max(0., old_n - u[n] / entry(n, n));
            add_column(n, new_n - old_n);
            lambda[n] = new_n;

            // The tangents: the impulse that stops sliding (2 x 2 block) if it lies in the
            // friction disk; else a step along -u_t scaled by the block's mean diagonal,
            // cut back to the disk. The isotropic step matters: cutting back the 2 x 2
            // solution would converge to an impulse along -B u_t, not against the sliding
            // velocity u_t as Coulomb's maximal dissipation wants (B, the tangential block
            // of W, is not a multiple of the identity).
            double       new_t1 = 0, new_t2 = 0;
            const double bound  = friction[j] * new_n;
            if (bound > 0)
              {
                const double a = entry(t1, t1), b = entry(t1, t2), d = entry(t2, t2);
                const double determinant = a * d - b * b;
                new_t1 = old_t1 - (d * u[t1] - b * u[t2]) / determinant;
                new_t2 = old_t2 - (a * u[t2] - b * u[t1]) / determinant;
                if (std::hypot(new_t1, new_t2) > bound)
                  {
                    const double mean_diagonal = (a + d) / 2;
                    new_t1                     = old_t1 - u[t1] / mean_diagonal;
                    new_t2                     = old_t2 - u[t2] / mean_diagonal;
                    const double size          = std::hypot(new_t1, new_t2);
                    if (size > bound)
                      {
                        new_t1 *= bound / size;
                        new_t2 *= bound / size;
                      }
                  }
              }
            add_column(t1, new_t1 - old_t1);
            add_column(t2, new_t2 - old_t2);
            lambda[t1] = new_t1;
            lambda[t2] = new_t2;

            // How much this visit moved the contact's velocities.
            result.residual = std::max({result.residual, std::abs(entry(n, n) * (new_n - old_n)),
                                        std::abs(entry(t1, t1) * (new_t1 - old_t1)),
                                        std::abs(entry(t2, t2) * (new_t2 - old_t2))});
          }
        result.converged = result.residual <= settings.tolerance;
      }
    return result;
  }
} // namespace warpchol::fem
