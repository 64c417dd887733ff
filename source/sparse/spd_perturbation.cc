#include <warpchol/base/exceptions.h>
#include <warpchol/sparse/conversions.h>
#include <warpchol/sparse/spd_perturbation.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace warpchol::sparse
{
  namespace
  {
    /** splitmix64's finalizer: a portable, well-mixed 64-bit hash. */
    std::uint64_t mix(std::uint64_t x)
    {
      x += 0x9e3779b97f4a7c15ULL;
      x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
      x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
      return x ^ (x >> 31);
    }

    /** A hash mapped to [0, 1) with 53 random bits. */
    double unit_interval(const std::uint64_t h)
    {
      return static_cast<double>(h >> 11) * 0x1.0p-53;
    }
  } // namespace

  void perturb_columns_spd(CSCMatrix &matrix, const std::vector<Index> &columns,
                           const std::uint64_t seed, const double eps)
  {
    const Index       n = matrix.n_cols;
    std::vector<bool> in_set(n, false);
    for (const Index j : columns)
      {
        if (j < 0 || j >= n)
          throw InputError("column " + std::to_string(j) + " out of range [0, " +
                           std::to_string(n) + ")");
        in_set[j] = true;
      }
    std::vector<double> diagonal(n, 0.);
    for (Index j = 0; j < n; ++j)
      diagonal[j] = std::abs(matrix(j, j));

    // The random value of pair {i,j} is a hash of (seed, max, min): both triangles of a
    // full-storage matrix get the same value without a second pass.
    auto pair_value = [seed](Index i, Index j) {
      if (i < j)
        std::swap(i, j);
      const std::uint64_t h = mix(seed ^ mix(static_cast<std::uint64_t>(i) * 0x100000001b3ULL +
                                              static_cast<std::uint64_t>(j)));
      return 2. * unit_interval(h) - 1.;
    };
    std::vector<double> added_to_diagonal(n, 0.);
    for (Index j = 0; j < n; ++j)
      if (in_set[j])
        for (Index k = matrix.column_start[j]; k < matrix.column_start[j + 1]; ++k)
          {
            const Index i = matrix.row_index[k];
            if (i == j || !in_set[i])
              continue;
            const double e = eps * pair_value(i, j) * std::sqrt(diagonal[i] * diagonal[j]);
            matrix.values[k] += e;
            // Diagonal dominance of E, counted once per stored triangle entry.
            added_to_diagonal[j] += std::abs(e);
            if (matrix.storage == Storage::lower)
              added_to_diagonal[i] += std::abs(e);
          }
    for (Index j = 0; j < n; ++j)
      if (in_set[j])
        for (Index k = matrix.column_start[j]; k < matrix.column_start[j + 1]; ++k)
          if (matrix.row_index[k] == j)
            matrix.values[k] += added_to_diagonal[j] + eps * diagonal[j];
  }

  std::vector<Index> random_columns(const Index n, const Index count, const std::uint64_t seed)
  {
    std::vector<Index> all(n);
    std::iota(all.begin(), all.end(), Index(0));
    // Partial Fisher-Yates with the portable hash: the same columns on every platform.
    const Index selected = std::min(count, n);
    for (Index k = 0; k < selected; ++k)
      {
        const auto h = mix(seed + static_cast<std::uint64_t>(k) * 0x9e3779b97f4a7c15ULL);
        const Index pick = k + static_cast<Index>(unit_interval(h) * static_cast<double>(n - k));
        std::swap(all[k], all[std::min(pick, n - 1)]);
      }
    all.resize(selected);
    std::sort(all.begin(), all.end());
    return all;
  }

  std::vector<Index> local_vertex_columns(const CSCMatrix &matrix, const int block_size,
                                          const Index n_vertices, const std::uint64_t seed)
  {
    const CSCMatrix full       = to_full_storage(matrix);
    const Index     n_total    = full.n_cols / block_size;
    const Index     wanted     = std::min(n_vertices, n_total);
    std::vector<bool>  reached(n_total, false);
    std::vector<Index> queue;
    // Breadth first from a random vertex; if its component is exhausted, restart from the
    // next unreached vertex.
    Index start = static_cast<Index>(unit_interval(mix(seed)) * static_cast<double>(n_total));
    for (std::size_t head = 0; static_cast<Index>(queue.size()) < wanted;)
      {
        if (head == queue.size())
          {
            while (reached[start])
              start = (start + 1) % n_total;
            reached[start] = true;
            queue.push_back(start);
          }
        const Index vertex = queue[head++];
        for (Index c = 0; c < block_size; ++c)
          {
            const Index j = vertex * block_size + c;
            for (Index k = full.column_start[j]; k < full.column_start[j + 1]; ++k)
              {
                const Index neighbour = full.row_index[k] / block_size;
                if (!reached[neighbour] && static_cast<Index>(queue.size()) < wanted)
                  {
                    reached[neighbour] = true;
                    queue.push_back(neighbour);
                  }
              }
          }
      }
    std::vector<Index> columns;
    for (const Index vertex : queue)
      for (Index c = 0; c < block_size; ++c)
        columns.push_back(vertex * block_size + c);
    std::sort(columns.begin(), columns.end());
    return columns;
  }

  CSCMatrix penalty_columns(const CSCMatrix &matrix, const std::vector<Index> &columns, const double factor)
  {
    CSCMatrix c = CSCMatrix::zero(matrix.n_rows, static_cast<Index>(columns.size()));
    for (std::size_t t = 0; t < columns.size(); ++t)
      {
        c.row_index.push_back(columns[t]);
        c.values.push_back(std::sqrt(factor * std::abs(matrix(columns[t], columns[t]))));
        c.column_start[t + 1] = static_cast<Index>(t + 1);
      }
    return c;
  }

  void add_outer_products(CSCMatrix &matrix, const CSCMatrix &c, const double sign)
  {
    const auto add = [&](const Index i, const Index j, const double value) {
      const auto first = matrix.row_index.begin() + matrix.column_start[j];
      const auto last  = matrix.row_index.begin() + matrix.column_start[j + 1];
      const auto found = std::lower_bound(first, last, i);
      if (found == last || *found != i)
        throw InputError("C C^T has an entry (" + std::to_string(i) + "," + std::to_string(j) +
                         ") the matrix does not store");
      matrix.values[found - matrix.row_index.begin()] += value;
    };
    for (Index t = 0; t < c.n_cols; ++t)
      for (Index a = c.column_start[t]; a < c.column_start[t + 1]; ++a)
        for (Index b = c.column_start[t]; b < c.column_start[t + 1]; ++b)
          {
            const Index i = c.row_index[a], j = c.row_index[b];
            if (matrix.storage == Storage::lower && i < j)
              continue;
            add(i, j, sign * c.values[a] * c.values[b]);
          }
  }
} // namespace warpchol::sparse
