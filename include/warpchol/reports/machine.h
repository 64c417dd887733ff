#pragma once

#include <warpchol/base/simd.h>

#include <string>

/**
 * @file
 * What a benchmark prints about the machine it ran on, so that its figures can be read
 * against the machine's ceilings: the CPU, the SIMD instructions the kernels were built
 * run on, dgemm's flop rate and the memory's read bandwidth on one thread.
 */
namespace warpchol::app
{
  /** The CPU's model name with its family and model (/proc/cpuinfo), or "unknown CPU". */
  std::string cpu_name();

  /**
   * The SIMD target the kernels of @p family run on (chosen at run time, or forced by
   * WARPCHOL_SIMD_TARGET): avx512, avx2, sse4 or baseline on x86-64.
   */
  std::string simd_target(simd::Family family = simd::Family::element);

  /**
   * The per-target tables mark "slow" a kernel whose family's default target takes more
   * than this times the fastest target's time (issue 36's goal).
   */
  constexpr double slow_default_ratio = 1.15;

  /**
   * The read bandwidth of one thread in GB/s: the best of a few sums over 256 MiB, far
   * more than any cache holds (the bound of the memory-bound solves).
   */
  double measure_read_bandwidth();

  /**
   * One line: "machine: CPU, SIMD target T (this CPU: targets), dgemm G GFLOP/s (OpenBLAS
   * kernels), read B GB/s (one thread)",
   * measured now (about half a second).
   */
  std::string describe_machine();
} // namespace warpchol::app
