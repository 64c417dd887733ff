#pragma once

#include <string>

/**
 * @file
 * What a benchmark prints about the machine it ran on, so that its figures can be read
 * against the machine's ceilings: the CPU, the SIMD instructions the kernels were built
 * for, dgemm's flop rate and the memory's read bandwidth on one thread.
 */
namespace warpchol::app
{
  /** The CPU's model name (/proc/cpuinfo), or "unknown CPU". */
  std::string cpu_name();

  /** The widest SIMD instruction set the element and update kernels were compiled for: avx512, avx2, sse2 or none. */
  std::string simd_target();

  /**
   * The read bandwidth of one thread in GB/s: the best of a few sums over 256 MiB, far
   * more than any cache holds (the bound of the memory-bound solves).
   */
  double measure_read_bandwidth();

  /**
   * One line: "machine: CPU, SIMD target T, dgemm G GFLOP/s, read B GB/s (one thread)",
   * measured now (about half a second).
   */
  std::string describe_machine();
} // namespace warpchol::app
