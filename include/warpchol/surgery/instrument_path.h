#pragma once

#include <warpchol/fem/small_dense.h>

#include <vector>

/**
 * @file
 * The path of an instrument as a haptic device records it: samples of time and position,
 * linear in between (issue 27).
 */
namespace warpchol::fem
{
  /**
   * Samples (t_k, p_k) of an instrument's motion, t_k increasing, each p_k a few numbers
   * (a position: 3; a blade's two ends: 6). Between samples the path is linear; before the
   * first sample and after the last it holds (whoever uses a path checks that it covers
   * the times of its use: app/path_file.h).
   */
  class InstrumentPath
  {
  public:
    InstrumentPath() = default;
    /** @p values holds @p n_values numbers per sample, sample after sample. */
    InstrumentPath(std::vector<double> times, std::vector<double> values, unsigned int n_values);

    /** Whether there are no samples (no path). */
    bool empty() const;
    unsigned int n_samples() const;
    /** The values of a sample (3 or more). */
    unsigned int values_per_sample() const;
    double       start_time() const;
    double       end_time() const;

    /** The path at @p time: values @p first to @p first + 2, interpolated linearly. */
    Vector3 position(double time, unsigned int first = 0) const;

    /** The sample times strictly between @p from and @p to: where the path bends. */
    std::vector<double> times_between(double from, double to) const;

  private:
    std::vector<double> times;
    std::vector<double> values;
    unsigned int        n_values = 0;
  };
} // namespace warpchol::fem
