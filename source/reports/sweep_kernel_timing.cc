#include <warpchol/reports/sweep_kernel_timing.h>
#include <warpchol/reports/kernel_timing.h>
#include <warpchol/reports/machine.h>

#include <algorithm>

namespace warpchol::app
{
  void print_sweep_kernel_table(std::ostream &out, const Scene &scene, const std::vector<fem::Vector3> &positions,
                                const std::vector<SweepRow> &rows)
  {
    double estimate_seconds = 0;
    for (const auto &row : rows)
      if (row.phases.t_error_estimate() > 0 && row.steps > 0)
        estimate_seconds = estimate_seconds > 0 ? std::min(estimate_seconds, row.phases.t_error_estimate() / row.steps) :
                                                  row.phases.t_error_estimate() / row.steps;
    print_kernel_table(out, {{simd_target(), time_kernels(scene, positions)}},
                       scene.body().n_elements(), 1e9 * estimate_seconds / scene.body().n_elements());
  }
} // namespace warpchol::app
