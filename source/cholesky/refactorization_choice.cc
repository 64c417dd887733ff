#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/simd.h>
#include <warpchol/cholesky/refactorization_choice.h>

#include <algorithm>

namespace warpchol::cholesky
{
  std::string to_string(const RefactorizationMethod method)
  {
    switch (method)
      {
        case RefactorizationMethod::none:
          return "none";
        case RefactorizationMethod::update:
          return "update";
        case RefactorizationMethod::partial:
          return "partial";
        case RefactorizationMethod::full:
          return "full";
      }
    return "unknown";
  }

  std::string to_string(const ChangeMethod method)
  {
    return name_of(change_method_names, method);
  }

  ChangeMethod parse_change_method(const std::string &name)
  {
    return parse_name(change_method_names, name, "change method");
  }

  namespace
  {
    /** Index of a method that computes something in the rates. */
    std::size_t slot(const RefactorizationMethod method)
    {
      return method == RefactorizationMethod::update ? 0 : method == RefactorizationMethod::partial ? 1 : 2;
    }

    /** Weight of a new measurement in a rate's moving average. */
    constexpr double new_weight = 0.3;
  } // namespace

  RefactorizationCostModel::RefactorizationCostModel(const bool fixed_rates)
    : fixed_rates(fixed_rates)
  {
    // Fixed rates choose alike on every machine: neither the SIMD target nor the rank moves them.
    rates[0] = (fixed_rates ? fixed_update_rate_ratio : update_rate_prior()) * default_rate;
  }

  double RefactorizationCostModel::efficiency(const RefactorizationMethod method, const unsigned int rank) const
  {
    return method == RefactorizationMethod::update && !fixed_rates ? rank_efficiency(rank) : 1.;
  }

  double RefactorizationCostModel::rank_efficiency(const unsigned int rank)
  {
    const double k = std::max(1u, rank);
    return k / (k + update_half_rank);
  }

  double RefactorizationCostModel::update_rate_prior()
  {
    const std::string target = simd::current_target(simd::Family::update);
    return target == "avx512" ? 1. : target == "avx2" ? 0.7 : target == "sse4" ? 0.4 : 0.25;
  }

  double RefactorizationCostModel::predicted_seconds(const RefactorizationMethod method, const double flops,
                                                     const unsigned int rank) const
  {
    if (method == RefactorizationMethod::none)
      return 0.;
    return flops / (rates[slot(method)] * efficiency(method, rank));
  }

  void RefactorizationCostModel::record(const RefactorizationMethod method, const double flops, const double seconds,
                                        const unsigned int rank)
  {
    // Too little work to time, or a method that computed nothing.
    if (fixed_rates || method == RefactorizationMethod::none || !(flops > least_timed_flops) || !(seconds > 0))
      return;
    const double      rate = flops / seconds / efficiency(method, rank);
    const std::size_t k    = slot(method);
    rates[k]               = measured[k] ? (1 - new_weight) * rates[k] + new_weight * rate : rate;
    measured[k]            = true;
    // A factorization's rate stands for the methods not measured yet.
    if (method != RefactorizationMethod::update)
      for (const std::size_t other : {std::size_t(1), std::size_t(2)})
        if (!measured[other])
          rates[other] = rates[k];
    if (!measured[0] && method != RefactorizationMethod::update)
      rates[0] = update_rate_prior() * rates[k];
  }

  bool RefactorizationCostModel::knows_factorization_rate() const
  {
    return fixed_rates || measured[slot(RefactorizationMethod::partial)] || measured[slot(RefactorizationMethod::full)];
  }

  void RefactorizationCostModel::save(BinaryWriter &writer) const
  {
    for (std::size_t k = 0; k < rates.size(); ++k)
      {
        writer.write(rates[k]);
        writer.write(measured[k]);
      }
  }

  void RefactorizationCostModel::load(BinaryReader &reader)
  {
    for (std::size_t k = 0; k < rates.size(); ++k)
      {
        reader.read(rates[k]);
        reader.read(measured[k]);
        if (!(rates[k] > 0))
          reader.fail("a refactorization rate is not positive (corrupt)");
      }
  }
} // namespace warpchol::cholesky
