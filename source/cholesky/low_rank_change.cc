#include <warpchol/cholesky/low_rank_change.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace warpchol::cholesky
{
  std::vector<Index> touched_rows(const std::vector<PermutedMatrix::Change> &changes)
  {
    std::vector<Index> rows;
    rows.reserve(2 * changes.size());
    for (const auto &change : changes)
      {
        rows.push_back(change.row);
        rows.push_back(change.column);
      }
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    return rows;
  }

  LowRankChange low_rank_form(const Index n, const std::vector<PermutedMatrix::Change> &changes)
  {
    const std::vector<Index> rows = touched_rows(changes);
    const Index              m    = static_cast<Index>(rows.size());
    const auto position = [&](const Index row) { return std::lower_bound(rows.begin(), rows.end(), row) - rows.begin(); };
    // Delta on S, dense, lower triangle (column-major, m x m).
    std::vector<double> delta(static_cast<std::size_t>(m * m), 0.);
    double              largest_diagonal = 0, largest_off_diagonal = 0;
    for (const auto &change : changes)
      {
        const Index i = position(std::max(change.row, change.column)), j = position(std::min(change.row, change.column));
        delta[i + j * m] += change.delta;
      }
    for (Index j = 0; j < m; ++j)
      {
        largest_diagonal = std::max(largest_diagonal, std::abs(delta[j + j * m]));
        for (Index i = j + 1; i < m; ++i)
          largest_off_diagonal = std::max(largest_off_diagonal, std::abs(delta[i + j * m]));
      }
    // Gill, Murray and Wright's bound: |G_ij|^2 |d_j| <= beta^2, and the least pivot kept.
    const double eps   = std::numeric_limits<double>::epsilon();
    const double beta2 = std::max({largest_diagonal, m > 1 ? largest_off_diagonal / std::sqrt(double(m * m - 1)) : 0.,
                                   eps * (largest_diagonal + largest_off_diagonal)});
    const double least_pivot = eps * (largest_diagonal + largest_off_diagonal);

    LowRankChange form;
    form.c = sparse::CSCMatrix::zero(n, 0, sparse::Storage::full);
    form.c.column_start.assign(1, 0);
    const auto add_column = [&](const std::vector<std::pair<Index, double>> &entries, const double sign) {
      for (const auto &[row, value] : entries)
        {
          form.c.row_index.push_back(row);
          form.c.values.push_back(value);
        }
      form.c.column_start.push_back(static_cast<Index>(form.c.row_index.size()));
      form.signs.push_back(sign);
      ++form.c.n_cols;
    };
    std::vector<std::pair<Index, double>> entries;
    for (Index j = 0; j < m; ++j)
      {
        double *column   = delta.data() + j * m;
        double  largest  = 0;
        for (Index i = j + 1; i < m; ++i)
          largest = std::max(largest, std::abs(column[i]));
        const double pivot = column[j];
        if (largest == 0 && std::abs(pivot) <= least_pivot)
          continue; // nothing left in this row and column (to rounding)
        const double sign   = pivot < 0 ? -1. : 1.;
        const double raised = sign * std::max({std::abs(pivot), largest * largest / beta2, least_pivot});
        // C's column sqrt|d| G(:,j), G(j,j) = 1: column / d * sqrt|d|.
        const double root = std::sqrt(std::abs(raised));
        entries.clear();
        entries.emplace_back(rows[j], root);
        for (Index i = j + 1; i < m; ++i)
          if (column[i] != 0)
            entries.emplace_back(rows[i], column[i] * sign / root);
        add_column(entries, sign);
        if (raised != pivot)
          add_column({{rows[j], std::sqrt(std::abs(raised - pivot))}}, raised > pivot ? -1. : 1.);
        // The trailing matrix loses G(:,j) d G(:,j)^T = column column^T / d.
        for (Index k = j + 1; k < m; ++k)
          if (column[k] != 0)
            {
              const double scaled = column[k] / raised;
              double      *target = delta.data() + k * m;
              for (Index i = k; i < m; ++i)
                target[i] -= column[i] * scaled;
            }
      }
    return form;
  }
} // namespace warpchol::cholesky
