#pragma once

#include <warpchol/contact/contact_compliance.h>

#include <vector>

/**
 * @file
 * Signorini's conditions with Coulomb's friction cone on a compliance W, by projected
 * Gauss-Seidel over the contacts (SOFA's GenericConstraintSolver with
 * UnilateralInteractionConstraint's resolution): the small problem of a contact step.
 */
namespace warpchol::fem
{
  /** When projected Gauss-Seidel stops. */
  struct GaussSeidelSettings
  {
    unsigned int max_iterations = 200;
    /**
     * Stop when a sweep changes no contact's velocity by more than this (m/s): the change
     * of its impulse times the diagonal block of W.
     */
    double tolerance = 1e-9;
  };

  /** What a solve did. */
  struct GaussSeidelResult
  {
    unsigned int iterations = 0;
    /** The largest change of a contact's velocity (m/s) in the last sweep. */
    double residual = 0;
    bool   converged = true;
  };

  /**
   * Solve for the impulses lambda of W's contacts, each three rows (its normal, then two
   * tangents), given their velocities without impulses @p free_velocity and the compliance
   * @p w (m = 3 n_contacts rows, whole or factored): the contact velocities are
   *   u = free_velocity + W lambda,
   * and each contact j has u_n >= 0, lambda_n >= 0, u_n lambda_n = 0 (Signorini), and
   * |lambda_t| <= mu_j lambda_n, with lambda_t opposing u_t when it slides (Coulomb, the
   * static and dynamic coefficients equal: @p friction[j]).
   *
   * Gauss-Seidel visits the contacts in order: the normal impulse from the normal row,
   * projected on lambda_n >= 0, then the tangential impulse from the 2 x 2 tangential
   * block, projected on the disk of radius mu lambda_n. @p lambda holds the starting guess
   * (a kept solution: warm start) or is resized to zeros.
   */
  GaussSeidelResult solve_friction_cone(const ContactCompliance &w, const std::vector<double> &free_velocity,
                                        const std::vector<double> &friction, const GaussSeidelSettings &settings,
                                        std::vector<double> &lambda);

  /**
   * The same from W @p lambda as @p w_lambda holds it (ContactCompliance::Product of @p w
   * at @p lambda, which a caller that solves again keeps), which then holds W lambda at
   * the returned lambda: no product of W at the start or for the caller after.
   */
  GaussSeidelResult solve_friction_cone(const ContactCompliance &w, const std::vector<double> &free_velocity,
                                        const std::vector<double> &friction, const GaussSeidelSettings &settings,
                                        std::vector<double> &lambda, ContactCompliance::Product &w_lambda);
} // namespace warpchol::fem
