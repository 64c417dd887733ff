#include <warpchol/base/exceptions.h>
#include <warpchol/surgery/instrument_path.h>

#include <algorithm>

namespace warpchol::fem
{
  InstrumentPath::InstrumentPath(std::vector<double> times, std::vector<double> values, const unsigned int n_values)
    : times(std::move(times))
    , values(std::move(values))
    , n_values(n_values)
  {
    if (n_values < 3 || this->values.size() != this->times.size() * n_values)
      throw InputError("an instrument path needs at least 3 values per sample, as many samples of values as times");
  }

  bool InstrumentPath::empty() const
  {
    return times.empty();
  }

  unsigned int InstrumentPath::values_per_sample() const
  {
    return n_values;
  }

  unsigned int InstrumentPath::n_samples() const
  {
    return static_cast<unsigned int>(times.size());
  }

  double InstrumentPath::start_time() const
  {
    return times.front();
  }

  double InstrumentPath::end_time() const
  {
    return times.back();
  }

  Vector3 InstrumentPath::position(const double time, const unsigned int first) const
  {
    const auto at = [&](const std::size_t k) {
      return Vector3(values[k * n_values + first], values[k * n_values + first + 1], values[k * n_values + first + 2]);
    };
    if (time <= times.front())
      return at(0);
    if (time >= times.back())
      return at(times.size() - 1);
    // The sample at or before time, and the next one.
    const std::size_t k = std::upper_bound(times.begin(), times.end(), time) - times.begin() - 1;
    const double      w = (time - times[k]) / (times[k + 1] - times[k]);
    // At a sample (w = 0) this is the sample itself, to the bit.
    return (1 - w) * at(k) + w * at(k + 1);
  }

  std::vector<double> InstrumentPath::times_between(const double from, const double to) const
  {
    const auto begin = std::upper_bound(times.begin(), times.end(), from);
    const auto end   = std::lower_bound(begin, times.end(), to);
    return {begin, end};
  }
} // namespace warpchol::fem
