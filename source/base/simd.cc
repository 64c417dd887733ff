#include <warpchol/base/format.h>
#include <warpchol/base/simd.h>

#include <hwy/highway.h>
#include <hwy/targets.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdlib>
#include <mutex>
#include <stdexcept>

namespace warpchol::simd
{
  namespace
  {
    /** Our name of Highway's target bit @p target. */
    std::string name_of(const std::int64_t target)
    {
#if HWY_ARCH_X86
      switch (target)
        {
          case HWY_AVX3:
            return "avx512";
          case HWY_AVX2:
            return "avx2";
          case HWY_SSE4:
            return "sse4";
          default:
            break;
        }
#endif
      if (target == HWY_EMU128 || target == HWY_SCALAR)
        return "baseline";
      std::string name = hwy::TargetName(target);
      std::transform(name.begin(), name.end(), name.begin(),
                     [](const unsigned char c) { return static_cast<char>(std::tolower(c)); });
      return name;
    }

    /**
     * The targets compiled in that the CPU supports, before any forcing: within an
     * architecture Highway gives better targets lower bits (HWY_AVX3 < HWY_AVX2 < HWY_SSE4).
     */
    std::int64_t cpu_targets()
    {
      static const std::int64_t mask = [] {
        hwy::SetSupportedTargetsForTest(0);
        return hwy::SupportedTargets() & HWY_TARGETS;
      }();
      return mask;
    }

    /**
     * The element family's target unless told otherwise (the others take the best): AVX2
     * where the CPU has it, even with AVX-512, else the best. Its kernels work on 8 lanes
     * of 3x3 blocks, which AVX2 holds in two registers as AVX-512 in one, and run as fast
     * or faster on AVX2 where 512-bit instructions are executed in two halves or lower the
     * clock (doc/targets).
     */
    std::int64_t default_target(const std::int64_t all)
    {
#if HWY_ARCH_X86
      if (all & HWY_AVX2)
        return HWY_AVX2;
#endif
      return all & -all;
    }

    /** Whether the choice is "default": each family then runs its own default target. */
    std::atomic<bool> family_defaults{true};

    /** Used up once WARPCHOL_SIMD_TARGET was read, or a target chosen explicitly (which then holds). */
    std::once_flag &environment_read()
    {
      static std::once_flag flag;
      return flag;
    }

    /** Make @p name the target of every dispatch from now on. */
    void choose(const std::string &name)
    {
      static std::mutex                 mutex;
      const std::lock_guard<std::mutex> lock(mutex);
      const std::int64_t                all    = cpu_targets();
      std::int64_t                      chosen = 0;
      if (name == "best")
        chosen = all & -all;
      else if (name == "default")
        chosen = default_target(all);
      else
        for (std::int64_t bits = all; bits != 0; bits &= bits - 1)
          if (name_of(bits & -bits) == name)
            {
              chosen = bits & -bits;
              break;
            }
      if (chosen == 0)
        {
          std::vector<std::string> names = available_targets();
          names.insert(names.end(), {"best", "default"});
          throw std::invalid_argument("SIMD target '" + name + "' is not available on this CPU (available: " +
                                      alternatives(names) + ")");
        }
      family_defaults = name == "default";
      // Only the chosen target is supported from now on: Highway's dispatch takes it.
      hwy::SetSupportedTargetsForTest(chosen);
      hwy::GetChosenTarget().Update(hwy::SupportedTargets());
    }
  } // namespace

  std::vector<std::string> available_targets()
  {
    std::vector<std::string> names;
    for (std::int64_t bits = cpu_targets(); bits != 0; bits &= bits - 1)
      names.push_back(name_of(bits & -bits));
    return names;
  }

  std::int64_t target_bit(const Family family)
  {
    use_target_from_environment();
    if (family != Family::element && family_defaults)
      {
        const std::int64_t all = cpu_targets();
        return all & -all;
      }
    const std::int64_t bits = hwy::SupportedTargets() & HWY_TARGETS;
    return bits & -bits;
  }

  std::size_t dispatch_index(const Family family)
  {
    const std::int64_t target = target_bit(family);
    return hwy::Num0BitsBelowLS1Bit_Nonzero64(static_cast<std::uint64_t>(
      (HWY_CHOSEN_TARGET_SHIFT(target) | HWY_CHOSEN_TARGET_MASK_SCALAR) & HWY_CHOSEN_TARGET_MASK_TARGETS));
  }

  std::string current_target(const Family family)
  {
    return name_of(target_bit(family));
  }

  void use_target(const std::string &name)
  {
    std::call_once(environment_read(), [] {});
    choose(name);
  }

  void use_target_from_environment()
  {
    std::call_once(environment_read(), [] {
      const char       *value = std::getenv("WARPCHOL_SIMD_TARGET");
      const std::string name  = value != nullptr && *value != '\0' ? value : "default";
      try
        {
          choose(name);
        }
      catch (const std::invalid_argument &error)
        {
          throw std::invalid_argument(std::string("WARPCHOL_SIMD_TARGET: ") + error.what());
        }
    });
  }
} // namespace warpchol::simd
