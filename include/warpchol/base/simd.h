#ifndef warpchol_base_simd_h
#define warpchol_base_simd_h

#include <string>
#include <vector>

/**
 * The SIMD target of warpchol's own kernels, chosen at run time.
 *
 * The kernels (polar decompositions, the fused element pass, the assembly of A, the
 * corotated product, the update kernel, the single-precision solve) are compiled once per
 * target with Google Highway's foreach_target, and each call goes to the default target
 * (AVX2 where the CPU has it, even with AVX-512, which ran them no faster on the machines
 * measured; else the best it has), unless one is forced: by use_target(), or by the environment variable
 * WARPCHOL_SIMD_TARGET (read at the first kernel call), as the sanitizer stage forces the
 * baseline. A target's name: "avx512", "avx2", "sse4", "baseline" on x86-64 (Highway's own
 * name, lower case, elsewhere).
 */
namespace warpchol::simd
{
  /** The targets compiled in that this CPU runs, best first; the last is the baseline. */
  std::vector<std::string> available_targets();

  /** The target the kernels run now. */
  std::string current_target();

  /**
   * Run the kernels on the target @p name ("best": the widest available; "default": AVX2
   * where available, else the best); an explicit choice
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
