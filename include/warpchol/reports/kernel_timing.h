#pragma once

#include <warpchol/app/scene.h>
#include <warpchol/fem/elastic_body.h>

#include <ostream>
#include <string>
#include <utility>
#include <vector>

/**
 * @file
 * The cost per element of the element kernels (ns per tet), as the benchmarks print them:
 * the threshold sweep on the target that runs, warpchol-kernels on every target the CPU has.
 */
namespace warpchol::app
{
  /** ns per tet of each element kernel, at one configuration of a scene. */
  struct KernelTimes
  {
    double svd_rotation = 0, polar_rotation = 0, batched_rotation = 0;
    double fused_pass = 0, fused_pass_nodal = 0, corotated_product = 0;
    double assembly = 0, reassembly_of_a_tenth = 0;
  };

  /**
   * Time the kernels of @p scene at the configuration @p positions on the SIMD target that
   * runs now: the best of a few repetitions of a whole pass over the elements, on the
   * scene's threads.
   */
  KernelTimes time_kernels(const Scene &scene, const std::vector<fem::Vector3> &positions);

  /**
   * time_kernels() on each of @p targets (simd::use_target(); "" runs the target that runs
   * now), kernel by kernel, the targets in turn, @p rounds times, the best of the rounds
   * kept: a burst of load on a shared machine then slows one round of one kernel on one
   * target. Leaves the last target chosen.
   */
  std::vector<KernelTimes> time_kernels_on_targets(const Scene &scene, const std::vector<fem::Vector3> &positions,
                                                   const std::vector<std::string> &targets, unsigned int rounds);

  /** The default target of each family of element kernels, for the table's last column. */
  struct DefaultTargets
  {
    std::string element, assembly;

    /** The families' defaults that run now (simd::current_target()). */
    static DefaultTargets current();
  };

  /**
   * The table of @p columns (a name, such as the target, and its times) for @p n_elements
   * tets; @p estimate_ns_per_tet, if > 0, adds the WCC error estimate (measured in runs,
   * the same for every column). With several columns and @p defaults given, a last column
   * gives each kernel's family's default target's time over the fastest's, marked "slow"
   * past 1.15.
   */
  void print_kernel_table(std::ostream &out, const std::vector<std::pair<std::string, KernelTimes>> &columns,
                          unsigned int n_elements, double estimate_ns_per_tet = 0,
                          const DefaultTargets &defaults = {});
} // namespace warpchol::app
