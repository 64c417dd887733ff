#include <warpchol/base/exceptions.h>
#include <warpchol/contact/friction_cone_solver.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace warpchol::fem
{
  GaussSeidelResult solve_friction_cone(const ContactCompliance &w, const std::vector<double> &free_velocity,
                                        const std::vector<double> &friction, const GaussSeidelSettings &settings,
                                        std::vector<double> &lambda)
  {
    if (lambda.size() != 3 * w.n_contacts())
      lambda.assign(3 * w.n_contacts(), 0.);
    ContactCompliance::Product w_lambda(w, lambda);
    return solve_friction_cone(w, free_velocity, friction, settings, lambda, w_lambda);
  }

  GaussSeidelResult solve_friction_cone(const ContactCompliance &w, const std::vector<double> &free_velocity,
                                        const std::vector<double> &friction, const GaussSeidelSettings &settings,
                                        std::vector<double> &lambda, ContactCompliance::Product &w_lambda)
  {
    const std::size_t n_contacts = w.n_contacts(), m = 3 * n_contacts;
    if (free_velocity.size() != m || friction.size() != n_contacts || lambda.size() != m)
      throw Error("solve_friction_cone(): " + std::to_string(free_velocity.size()) + " rows, " +
                  std::to_string(friction.size()) + " friction coefficients, " + std::to_string(lambda.size()) +
                  " impulses, W of " + std::to_string(m) + " rows");

    GaussSeidelResult result;
    result.converged = n_contacts == 0;
    for (result.iterations = 0; !result.converged && result.iterations < settings.max_iterations;)
      {
        ++result.iterations;
        result.residual = 0;
        for (std::size_t j = 0; j < n_contacts; ++j)
          {
            const std::size_t n = 3 * j, t1 = n + 1, t2 = n + 2;
            const Matrix3    &block = w.diagonal_block(j);
            const double      old_n = lambda[n], old_t1 = lambda[t1], old_t2 = lambda[t2];
            Vector3 u = w_lambda.velocity(j) + Vector3(free_velocity[n], free_velocity[t1], free_velocity[t2]);

            // The normal: the impulse that makes u_n vanish, or none if it separates. The
            // tangential velocities then move by the block's first column.
            const double new_n = std::max(0., old_n - u[0] / block(0, 0));
            u += block.col(0) * (new_n - old_n);

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
                const double a = block(1, 1), b = block(1, 2), d = block(2, 2);
                const double determinant = a * d - b * b;
                new_t1 = old_t1 - (d * u[1] - b * u[2]) / determinant;
                new_t2 = old_t2 - (a * u[2] - b * u[1]) / determinant;
                if (std::hypot(new_t1, new_t2) > bound)
                  {
                    const double mean_diagonal = (a + d) / 2;
                    new_t1                     = old_t1 - u[1] / mean_diagonal;
                    new_t2                     = old_t2 - u[2] / mean_diagonal;
                    const double size          = std::hypot(new_t1, new_t2);
                    if (size > bound)
                      {
                        new_t1 *= bound / size;
                        new_t2 *= bound / size;
                      }
                  }
              }
            w_lambda.add(j, Vector3(new_n - old_n, new_t1 - old_t1, new_t2 - old_t2));
            lambda[n]  = new_n;
            lambda[t1] = new_t1;
            lambda[t2] = new_t2;

            // How much this visit moved the contact's velocities.
            result.residual = std::max({result.residual, std::abs(block(0, 0) * (new_n - old_n)),
                                        std::abs(block(1, 1) * (new_t1 - old_t1)),
                                        std::abs(block(2, 2) * (new_t2 - old_t2))});
          }
        result.converged = result.residual <= settings.tolerance;
      }
    return result;
  }
} // namespace warpchol::fem
