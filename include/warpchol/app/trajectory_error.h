#pragma once

#include <warpchol/fem/small_dense.h>

#include <vector>

/**
 * @file
 * How far a run strays from a reference run of the same scene (the exact corotational
 * one): per step, and summed up over the steps.
 */
namespace warpchol::app
{
  /**
   * The distance of the vertex positions x from the reference positions x_ref of the same
   * step, both measures relative to the largest displacement of the reference,
   * D = max_i |x_ref_i - X_i| (X the rest positions), so that they read as fractions of
   * the motion whatever the mesh's size:
   *   max = max_i |x_i - x_ref_i| / D               (the worst vertex)
   *   rms = sqrt(mean_i |x_i - x_ref_i|^2) / D      (the typical vertex)
   * If the reference has not moved (D = 0), the distances themselves.
   */
  struct PositionError
  {
    double max = 0;
    double rms = 0;
  };

  /** The PositionError of @p positions against @p reference, the motion from @p rest. */
  PositionError position_error(const std::vector<fem::Vector3> &positions,
                               const std::vector<fem::Vector3> &reference,
                               const std::vector<fem::Vector3> &rest);

  /** The PositionError of every step of a run, summed up: largest, mean and last. */
  class TrajectoryError
  {
  public:
    /** Account for the error of the next step. */
    void add(const PositionError &step_error);

    unsigned int n_steps() const;
    /** Largest over the steps of the worst vertex's error. */
    double max_error() const;
    /** Mean over the steps of the worst vertex's error. */
    double mean_error() const;
    /** The worst vertex's error in the last step. */
    double last_error() const;
    /** Largest over the steps of the RMS error. */
    double max_rms_error() const;
    /** Mean over the steps of the RMS error. */
    double mean_rms_error() const;

  private:
    unsigned int  steps = 0;
    PositionError largest;
    PositionError sum;
    PositionError last;
  };
} // namespace warpchol::app
