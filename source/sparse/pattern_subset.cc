#include <warpchol/base/exceptions.h>
#include <warpchol/sparse/pattern_subset.h>

#include <cmath>

namespace warpchol::sparse
{
  std::string entry_name(const Index i, const Index j)
  {
    return "(" + std::to_string(i) + "," + std::to_string(j) + ")";
  }

  std::string non_finite_entry_message(const Index i, const Index j, const double value)
  {
    const std::string what = std::isnan(value) ? "NaN" : value > 0 ? "infinite (inf)" : "infinite (-inf)";
    return "matrix entry A" + entry_name(i, j) + " is " + what;
  }

  std::vector<Index> places_in_pattern(const Index        n,
                                       const Index *const pattern_start,
                                       const Index *const pattern_row,
                                       const Index *const subset_start,
                                       const Index *const subset_row,
                                       const Index        n_subset_entries,
                                       const bool         transposed)
  {
    const auto name = [&](const Index i, const Index j) { return transposed ? entry_name(j, i) : entry_name(i, j); };
    const char *const columns = transposed ? "row" : "column";
    if (subset_start[0] != 0 || subset_start[n] != n_subset_entries)
      throw MatrixError("invalid matrix: its " + std::string(columns) + " starts run from " +
                        std::to_string(subset_start[0]) + " to " + std::to_string(subset_start[n]) + ", expected 0 to " +
                        std::to_string(n_subset_entries));
    std::vector<Index> places(n_subset_entries);
    // place_of_row[i]: where row i of the current column lies in the pattern; -1 where the
    // pattern has no such entry, -2 once the matrix's entry took it.
    constexpr Index    outside = -1, taken = -2;
    std::vector<Index> place_of_row(n, outside);
    for (Index j = 0; j < n; ++j)
      {
        if (subset_start[j + 1] < subset_start[j])
          throw MatrixError("invalid matrix: its " + std::string(columns) + " starts decrease at " + columns + " " +
                            std::to_string(j + 1));
        for (Index p = pattern_start[j]; p < pattern_start[j + 1]; ++p)
          place_of_row[pattern_row[p]] = p;
        for (Index k = subset_start[j]; k < subset_start[j + 1]; ++k)
          {
            const Index i = subset_row[k];
            if (i < 0 || i >= n)
              throw MatrixError("invalid matrix: index " + std::to_string(i) + " out of range [0, " + std::to_string(n) +
                                ") in " + columns + " " + std::to_string(j));
            if (place_of_row[i] == outside)
              throw MatrixError("matrix entry A" + name(i, j) +
                                " lies outside the analyzed pattern (analyze the new pattern first)");
            if (place_of_row[i] == taken)
              throw MatrixError("matrix stores entry A" + name(i, j) + " twice");
            places[k]       = place_of_row[i];
            place_of_row[i] = taken;
          }
        for (Index p = pattern_start[j]; p < pattern_start[j + 1]; ++p)
          place_of_row[pattern_row[p]] = outside;
      }
    return places;
  }
} // namespace warpchol::sparse
