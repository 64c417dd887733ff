#include <warpchol/reports/machine.h>
#include <warpchol/base/format.h>
#include <warpchol/base/simd.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/cholesky/blas.h>

#include <algorithm>
#include <fstream>
#include <numeric>
#include <vector>

namespace warpchol::app
{
  std::string cpu_name()
  {
    // A virtual machine often shows a generic name ("AMD EPYC"): the family and model tell
    // the generations apart (AMD 25: Zen 3 and 4, 26: Zen 5; Intel 6, model 207: Emerald
    // Rapids).
    std::ifstream cpuinfo("/proc/cpuinfo");
    std::string   line, name, family, model;
    const auto    value = [&line]() {
      const auto colon = line.find(':');
      const auto start = colon == std::string::npos ? colon : line.find_first_not_of(" \t", colon + 1);
      return start == std::string::npos ? std::string() : line.substr(start);
    };
    while (std::getline(cpuinfo, line) && line.find_first_not_of(" \t") != std::string::npos)
      if (line.rfind("model name", 0) == 0)
        name = value();
      else if (line.rfind("cpu family", 0) == 0)
        family = value();
      else if (line.rfind("model", 0) == 0 && line.find_first_of(" \t") == 5)
        model = value();
    if (name.empty())
      return "unknown CPU";
    if (!family.empty() && !model.empty())
      name += " (family " + family + ", model " + model + ")";
    return name;
  }

  std::string simd_target(const simd::Family family)
  {
    return simd::current_target(family);
  }

  double measure_read_bandwidth()
  {
    const std::size_t   n = (std::size_t(256) << 20) / sizeof(double);
    std::vector<double> array(n, 1.);
    double              best = 0, sink = 0;
    for (int repeat = 0; repeat < 4; ++repeat)
      {
        const Stopwatch stopwatch;
        // Four sums side by side, so that the additions' latency does not bound it.
        double sums[4] = {0, 0, 0, 0};
        for (std::size_t i = 0; i + 3 < n; i += 4)
          for (int k = 0; k < 4; ++k)
            sums[k] += array[i + k];
        const double seconds = stopwatch.seconds();
        sink += sums[0] + sums[1] + sums[2] + sums[3];
        best = std::max(best, static_cast<double>(n * sizeof(double)) / seconds * 1e-9);
      }
    // The sum must be used, or the compiler may drop the loops.
    return sink > 0 ? best : 0.;
  }

  std::string describe_machine()
  {
    std::string available;
    for (const std::string &name : simd::available_targets())
      available += (available.empty() ? "" : " ") + name;
    return "machine: " + cpu_name() + ", SIMD target " + simd_target() + ", assembly " +
           simd_target(simd::Family::assembly) + ", updates " + simd_target(simd::Family::update) +
           " (this CPU: " + available + "), dgemm " +
           format_number(cholesky::blas::measure_dgemm_gflops(), 3) + " GFLOP/s (OpenBLAS " +
           cholesky::blas::kernel_name() + "), read " +
           format_number(measure_read_bandwidth(), 3) + " GB/s (one thread)";
  }
} // namespace warpchol::app
