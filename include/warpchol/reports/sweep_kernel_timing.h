#pragma once

#include <warpchol/app/scene.h>
#include <warpchol/fem/small_dense.h>
#include <warpchol/reports/sweep_table.h>

#include <ostream>
#include <vector>

/**
 * @file
 * The element kernels' cost in warpchol-threshold-sweep: ns per tet on this machine's SIMD
 * target (reports/kernel_timing.h), beside the error estimate's as the sweep's runs measured it.
 */
namespace warpchol::app
{
  /**
   * Time the element kernels of @p scene at @p positions and print their table on @p out,
   * with the cheapest error estimate per element that @p rows measured (none: 0).
   */
  void print_sweep_kernel_table(std::ostream &out, const Scene &scene, const std::vector<fem::Vector3> &positions,
                                const std::vector<SweepRow> &rows);
} // namespace warpchol::app
