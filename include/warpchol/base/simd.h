#ifndef warpchol_base_simd_h
#define warpchol_base_simd_h

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

/**
 * The SIMD target of warpchol's own kernels, chosen at run time.
 *
 * The kernels (polar decompositions, the fused element pass, the assembly of A, the
 * corotated product, the update kernel, the solves, contact's W lambda) are compiled once
 * per target with Google Highway's foreach_target, and each call goes to its family's
 * default target (Family), unless one is forced: by use_target(), or by the environment
 * variable WARPCHOL_SIMD_TARGET (read at the first kernel call), as the sanitizer stage
 * forces the baseline. A target's name: "avx512", "avx2", "sse4", "baseline" on x86-64
 * (Highway's own name, lower case, elsewhere).
 */
namespace warpchol::simd
{
  /** The targets compiled in that this CPU runs, best first; the last is the baseline. */
  std::vector<std::string> available_targets();

  /**
   * The families of kernels. Each family runs the chosen target; left to the default, each
   * takes its own default target, the fastest on the machines measured
   * (warpchol-solver-kernels and warpchol-kernels on every target, benchmarks/targets.sh):
   * - element: the rotations, the fused element pass, the corotated product, the solves
   *   and Gauss-Seidel's product W lambda (contact), AVX2 where the CPU has it (as fast as
   *   AVX-512 or faster, whose clock some CPUs lower), else the best;
   * - assembly: the assembly of A and its re-assembly, the best (widest) target: its
   *   blocks formed and scattered on AVX-512 ran 1.05-1.20x faster than on AVX2 on an
   *   AMD Zen 4 and an Intel Xeon of model 207, within 1.05x on a Sapphire Rapids;
   * - update: the update and downdate of the factor, the best (widest) target, whose 32
   *   registers of 8 doubles hold the carried columns of four times as many rows as AVX2's
   *   16 of 4.
   */
  enum class Family
  {
    element,
    assembly,
    update
  };

  /** The target the kernels of @p family run now. */
  std::string current_target(Family family = Family::element);

  /**
   * Highway's bit of the target the kernels of @p family run now (reads
   * WARPCHOL_SIMD_TARGET first, as use_target_from_environment() does): for a dispatch of
   * that family's kernels by its own target.
   */
  std::int64_t target_bit(Family family);

  /**
   * The entry of a Highway dispatch table (HWY_DISPATCH_TABLE of an HWY_EXPORT) for the
   * target @p family runs now: for a family whose default is not the element family's,
   * which HWY_DYNAMIC_DISPATCH would take.
   */
  std::size_t dispatch_index(Family family);

  /**
   * Run the kernels on the target @p name ("best": the widest available; "default": each
   * family's default, Family); an explicit choice
   * holds over WARPCHOL_SIMD_TARGET, which is then no longer read. Throws
   * std::invalid_argument, naming the available ones, if this CPU cannot run it or it was
   * not compiled in. Not to be called while kernels run on other threads.
   */
  void use_target(const std::string &name);

  /**
   * use_target() with the value of WARPCHOL_SIMD_TARGET if set (and "default" if not), once:
   * the kernels' dispatchers call it before their first call. Throws as use_target() does,
   * naming the variable.
   */
  void use_target_from_environment();
} // namespace warpchol::simd

#endif
