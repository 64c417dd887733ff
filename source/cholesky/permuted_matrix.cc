#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/cholesky/ordering.h>
#include <warpchol/cholesky/permuted_matrix.h>
#include <warpchol/sparse/pattern_subset.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <string>

namespace warpchol::cholesky
{
  namespace
  {
    using sparse::entry_name;

    std::string storage_name(const sparse::Storage storage)
    {
      return storage == sparse::Storage::full ? "both triangles" : "the lower triangle";
    }

    std::string asymmetry_message(const Index i, const Index j)
    {
      return "pattern is not symmetric: entry " + entry_name(i, j) + " is stored but " +
             entry_name(j, i) + " is not";
    }

    /** matrix.values, once checked to hold a value per entry. */
    const double *values_of(const sparse::CSCMatrix &matrix)
    {
      if (static_cast<Index>(matrix.values.size()) != static_cast<Index>(matrix.row_index.size()))
        throw MatrixError("matrix has " + std::to_string(matrix.values.size()) + " values for " +
                          std::to_string(matrix.row_index.size()) + " entries");
      return matrix.values.data();
    }
  } // namespace

  void PermutedMatrix::setup(const sparse::CSCMatrix &matrix, const std::vector<Index> &permutation)
  {
    if (matrix.n_rows != matrix.n_cols)
      throw MatrixError("matrix is not square: " + std::to_string(matrix.n_rows) + "x" +
                        std::to_string(matrix.n_cols));
    matrix.check_consistency();
    const Index n = matrix.n_cols;
    inverse_permutation = invert_permutation(permutation);
    this->permutation   = permutation;
    storage             = matrix.storage;
    analyzed_column_start = matrix.column_start;
    analyzed_row_index    = matrix.row_index;

    // Entry (i,j) of A lands at (max, min) of its permuted indices in C. With full storage
    // only the entry that lands in the lower triangle is a source; its twin is its mirror.
    auto is_source = [&](const Index pi, const Index pj) {
      return matrix.storage == sparse::Storage::lower || pi >= pj;
    };
    permuted_lower = sparse::CSCMatrix::zero(n, n, sparse::Storage::lower);
    for (Index j = 0; j < n; ++j)
      for (Index p = matrix.column_start[j]; p < matrix.column_start[j + 1]; ++p)
        {
          const Index pi = inverse_permutation[matrix.row_index[p]], pj = inverse_permutation[j];
          if (is_source(pi, pj))
            ++permuted_lower.column_start[std::min(pi, pj) + 1];
        }
    std::partial_sum(permuted_lower.column_start.begin(), permuted_lower.column_start.end(),
                     permuted_lower.column_start.begin());
    const Index nnz = permuted_lower.column_start[n];
    permuted_lower.row_index.resize(nnz);
    permuted_lower.values.assign(nnz, 0.);
    source.resize(nnz);
    std::vector<Index> next(permuted_lower.column_start.begin(), permuted_lower.column_start.end() - 1);
    for (Index j = 0; j < n; ++j)
      for (Index p = matrix.column_start[j]; p < matrix.column_start[j + 1]; ++p)
        {
          const Index pi = inverse_permutation[matrix.row_index[p]], pj = inverse_permutation[j];
          if (is_source(pi, pj))
            {
              const Index position                = next[std::min(pi, pj)]++;
              permuted_lower.row_index[position] = std::max(pi, pj);
              source[position]                    = p;
            }
        }
    // Sort each column by row, carrying the source positions along.
    entry_column.resize(nnz);
    std::vector<std::pair<Index, Index>> column_entries;
    for (Index j = 0; j < n; ++j)
      {
        const Index begin = permuted_lower.column_start[j], end = permuted_lower.column_start[j + 1];
        column_entries.clear();
        for (Index k = begin; k < end; ++k)
          column_entries.emplace_back(permuted_lower.row_index[k], source[k]);
        std::sort(column_entries.begin(), column_entries.end());
        for (Index k = begin; k < end; ++k)
          {
            permuted_lower.row_index[k] = column_entries[k - begin].first;
            source[k]                   = column_entries[k - begin].second;
            entry_column[k]             = j;
          }
      }

    // Full storage: every off-diagonal entry needs its twin, (i,j) <-> (j,i).
    mirror.assign(nnz, -1);
    if (matrix.storage == sparse::Storage::full)
      {
        for (Index j = 0; j < n; ++j)
          for (Index p = matrix.column_start[j]; p < matrix.column_start[j + 1]; ++p)
            {
              const Index i = matrix.row_index[p];
              const Index pi = inverse_permutation[i], pj = inverse_permutation[j];
              if (is_source(pi, pj))
                continue;
              // The twin (j,i) of this upper entry lands at row pj of column pi of C.
              const auto first = permuted_lower.row_index.begin() + permuted_lower.column_start[pi];
              const auto last = permuted_lower.row_index.begin() + permuted_lower.column_start[pi + 1];
              const auto found = std::lower_bound(first, last, pj);
              if (found == last || *found != pj)
                throw MatrixError(asymmetry_message(i, j));
              mirror[found - permuted_lower.row_index.begin()] = p;
            }
        for (Index k = 0; k < nnz; ++k)
          if (mirror[k] == -1 && permuted_lower.row_index[k] != entry_column[k])
            throw MatrixError(asymmetry_message(permutation[permuted_lower.row_index[k]],
                                                permutation[entry_column[k]]));
      }
    entry_of_input.assign(matrix.n_nonzeros(), -1);
    diagonal_entry.assign(n, -1);
    for (Index k = 0; k < nnz; ++k)
      {
        entry_of_input[source[k]] = k;
        if (mirror[k] != -1)
          entry_of_input[mirror[k]] = k;
        if (permuted_lower.row_index[k] == entry_column[k])
          diagonal_entry[entry_column[k]] = k;
      }
    input_values.clear();
    factored_values.clear();
    loaded = false;
  }

  std::vector<Index> PermutedMatrix::load(const sparse::CSCMatrix &matrix)
  {
    return load_values(values_in_analyzed_order(matrix, values_of(matrix)));
  }

  std::vector<Index> PermutedMatrix::load_columns(const sparse::CSCMatrix &matrix, const std::vector<Index> &columns)
  {
    return load_columns(matrix, values_of(matrix), columns);
  }

  std::vector<Index> PermutedMatrix::load(const sparse::CSCMatrix &matrix, const double *const values)
  {
    return load_values(values_in_analyzed_order(matrix, values));
  }

  const double *PermutedMatrix::values_in_analyzed_order(const sparse::CSCMatrix  &matrix,
                                                         const double *const       values,
                                                         const std::vector<Index> *listed_columns)
  {
    const Index n = permuted_lower.n_cols;
    if (matrix.n_rows != n || matrix.n_cols != n)
      throw MatrixError("matrix is " + std::to_string(matrix.n_rows) + "x" + std::to_string(matrix.n_cols) +
                        ", the analyzed one " + std::to_string(n) + "x" + std::to_string(n) +
                        " (analyze the new matrix first)");
    if (matrix.storage != storage)
      throw MatrixError("matrix stores " + storage_name(matrix.storage) + ", the analyzed one " +
                        storage_name(storage) + " (analyze the new matrix first)");
    if (listed_columns != nullptr && matrix.column_start == analyzed_column_start &&
        std::all_of(listed_columns->begin(), listed_columns->end(), [&](const Index j) {
          return std::equal(matrix.row_index.begin() + matrix.column_start[j],
                            matrix.row_index.begin() + matrix.column_start[j + 1],
                            analyzed_row_index.begin() + analyzed_column_start[j]);
        }))
      return values;
    if (matrix.column_start == analyzed_column_start && matrix.row_index == analyzed_row_index)
      return values;
    // Another pattern: a subset of the analyzed one is that pattern with zeros where it
    // has no entry (arithmetic drops explicit zeros); an entry outside is refused.
    if (static_cast<Index>(matrix.column_start.size()) != n + 1)
      throw MatrixError("invalid matrix: column_start has " + std::to_string(matrix.column_start.size()) +
                        " entries, expected " + std::to_string(n + 1));
    const std::vector<Index> places =
      sparse::places_in_pattern(n, analyzed_column_start.data(), analyzed_row_index.data(), matrix.column_start.data(),
                                matrix.row_index.data(), static_cast<Index>(matrix.row_index.size()));
    subset_values.assign(analyzed_row_index.size(), 0.);
    for (std::size_t k = 0; k < places.size(); ++k)
      subset_values[places[k]] = values[k];
    return subset_values.data();
  }

  void PermutedMatrix::refuse_value(const Index p, const double value) const
  {
    // The column of A's entry p: the last column that starts at or before it.
    const Index column =
      std::upper_bound(analyzed_column_start.begin(), analyzed_column_start.end(), p) - analyzed_column_start.begin() - 1;
    throw MatrixError(sparse::non_finite_entry_message(analyzed_row_index[p], column, value));
  }

  std::vector<Index> PermutedMatrix::load_changed_values(const double *const values)
  {
    const Index        n_input = static_cast<Index>(input_values.size());
    std::vector<Index> changed;
    for (Index p = 0; p < n_input; ++p)
      if (values[p] != input_values[p])
        changed.push_back(p);
    return load_entries(values, changed, true);
  }

  std::vector<Index> PermutedMatrix::load_columns(const sparse::CSCMatrix &matrix, const double *const values,
                                                  const std::vector<Index> &columns)
  {
    if (!loaded || input_values.size() != entry_of_input.size())
      return load_values(values_in_analyzed_order(matrix, values));
    const double *const analyzed_values = values_in_analyzed_order(matrix, values, &columns);
    std::vector<Index> changed;
    for (const Index j : columns)
      for (Index p = analyzed_column_start[j]; p < analyzed_column_start[j + 1]; ++p)
        if (analyzed_values[p] != input_values[p])
          changed.push_back(p);
    // Listed columns in increasing order, each once (the usual call), give their entries
    // in order already.
    if (std::adjacent_find(columns.begin(), columns.end(), std::greater_equal<Index>()) != columns.end())
      {
        std::sort(changed.begin(), changed.end());
        changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
      }
    return load_entries(analyzed_values, changed);
  }

  std::vector<Index> PermutedMatrix::load_entries(const double *const values, const std::vector<Index> &changed,
                                                  const bool every_change_listed)
  {
    if (changed.empty())
      return {};
    // Check everything before writing anything.
    for (const Index p : changed)
      if (!std::isfinite(values[p]))
        refuse_value(p, values[p]);
    if (storage == sparse::Storage::full)
      {
        const auto new_diagonal = [&](const Index column) {
          const Index k = diagonal_entry[column];
          return k < 0 ? 0. : std::abs(values[source[k]]);
        };
        for (const Index p : changed)
          {
            const Index k = entry_of_input[p];
            if (mirror[k] == -1)
              continue;
            const double value = values[source[k]], twin = values[mirror[k]];
            const Index  r = permuted_lower.row_index[k], c = entry_column[k];
            if (!sparse::symmetric_pair(value, twin, new_diagonal(r), new_diagonal(c)))
              throw MatrixError("matrix is not symmetric: A" + entry_name(permutation[r], permutation[c]) + " = " +
                                format_number(value) + " but A" + entry_name(permutation[c], permutation[r]) + " = " +
                                format_number(twin));
          }
      }
    // Most of A changed (a whole refactorization): C in its own order, each entry read from
    // where it comes from in A, and its columns come out in order. An entry of A that is
    // not listed holds its last value, which C holds too (add_low_rank() marks the entries
    // it changes in C so that the next load lists them).
    if (every_change_listed && 4 * static_cast<Index>(changed.size()) > permuted_lower.n_nonzeros())
      {
        std::vector<Index> changed_columns = copy_in_order(values, false);
        for (const Index p : changed)
          input_values[p] = values[p];
        return changed_columns;
      }
    // Each changed column once, marked: a sort of one column index per changed entry would
    // cost a good part of a large load.
    const Index        n = permuted_lower.n_cols;
    std::vector<char>  marked(n, 0);
    std::vector<Index> changed_columns;
    for (const Index p : changed)
      {
        const Index k   = entry_of_input[p];
        input_values[p] = values[p];
        if (source[k] == p && permuted_lower.values[k] != values[p])
          {
            permuted_lower.values[k] = values[p];
            if (!marked[entry_column[k]])
              {
                marked[entry_column[k]] = 1;
                changed_columns.push_back(entry_column[k]);
              }
          }
      }
    // In increasing order: a scan of the marks where many changed, else a sort of the few.
    if (static_cast<Index>(changed_columns.size()) > n / 16)
      {
        changed_columns.clear();
        for (Index j = 0; j < n; ++j)
          if (marked[j])
            changed_columns.push_back(j);
      }
    else
      std::sort(changed_columns.begin(), changed_columns.end());
    return changed_columns;
  }

  std::vector<Index> PermutedMatrix::copy_in_order(const double *const values, const bool all_columns)
  {
    const Index        nnz = permuted_lower.n_nonzeros();
    std::vector<Index> changed_columns;
    for (Index k = 0; k < nnz; ++k)
      {
        const double value = values[source[k]];
        if (all_columns || value != permuted_lower.values[k])
          if (changed_columns.empty() || changed_columns.back() != entry_column[k])
            changed_columns.push_back(entry_column[k]);
        permuted_lower.values[k] = value;
      }
    return changed_columns;
  }

  std::vector<Index> PermutedMatrix::load_values(const double *const values)
  {
    if (loaded && input_values.size() == entry_of_input.size())
      return load_changed_values(values);
    const Index nnz = permuted_lower.n_nonzeros();
    for (Index k = 0; k < nnz; ++k)
      {
        const double value = values[source[k]];
        if (!std::isfinite(value))
          refuse_value(source[k], value);
        // A twin that is not finite is named as such, not as an asymmetric pair.
        if (mirror[k] != -1 && !std::isfinite(values[mirror[k]]))
          refuse_value(mirror[k], values[mirror[k]]);
      }
    const std::vector<Index> changed_columns = copy_in_order(values, !loaded);
    if (storage == sparse::Storage::full)
      {
        // Diagonal values first, to scale the symmetry tolerance of each pair.
        std::vector<double> diagonal(permuted_lower.n_cols, 0.);
        for (Index k = 0; k < nnz; ++k)
          if (permuted_lower.row_index[k] == entry_column[k])
            diagonal[entry_column[k]] = std::abs(permuted_lower.values[k]);
        for (Index k = 0; k < nnz; ++k)
          if (mirror[k] != -1)
            {
              const double value = permuted_lower.values[k], twin = values[mirror[k]];
              const Index  r = permuted_lower.row_index[k], c = entry_column[k];
              if (!sparse::symmetric_pair(value, twin, diagonal[r], diagonal[c]))
                throw MatrixError("matrix is not symmetric: A" +
                                  entry_name(permutation[r], permutation[c]) + " = " +
                                  format_number(value) + " but A" +
                                  entry_name(permutation[c], permutation[r]) + " = " +
                                  format_number(twin));
            }
      }
    input_values.assign(values, values + entry_of_input.size());
    loaded = true;
    return changed_columns;
  }

  void PermutedMatrix::mark_factored()
  {
    factored_values = permuted_lower.values;
  }

  void PermutedMatrix::mark_factored(const std::vector<Index> &columns)
  {
    if (factored_values.size() != permuted_lower.values.size())
      {
        mark_factored();
        return;
      }
    for (const Index j : columns)
      std::copy(permuted_lower.values.begin() + permuted_lower.column_start[j],
                permuted_lower.values.begin() + permuted_lower.column_start[j + 1],
                factored_values.begin() + permuted_lower.column_start[j]);
  }

  std::vector<PermutedMatrix::Change> PermutedMatrix::changes_since_factored(const std::vector<Index> &columns) const
  {
    std::vector<Change> changes;
    if (factored_values.size() != permuted_lower.values.size())
      throw Error("changes_since_factored() before the first factorization");
    for (const Index j : columns)
      for (Index k = permuted_lower.column_start[j]; k < permuted_lower.column_start[j + 1]; ++k)
        if (permuted_lower.values[k] != factored_values[k])
          changes.push_back({permuted_lower.row_index[k], j, permuted_lower.values[k] - factored_values[k]});
    return changes;
  }

  bool PermutedMatrix::add_low_rank(const sparse::CSCMatrix &c, const std::vector<double> &signs)
  {
    bool inside = true;
    if (factored_values.size() != permuted_lower.values.size())
      mark_factored();
    for (Index t = 0; t < c.n_cols; ++t)
      for (Index a = c.column_start[t]; a < c.column_start[t + 1]; ++a)
        {
          // Column c.row_index[a] of C gets the products with the rows at and below it.
          const Index j     = c.row_index[a];
          const auto  first = permuted_lower.row_index.begin() + permuted_lower.column_start[j];
          const auto  last  = permuted_lower.row_index.begin() + permuted_lower.column_start[j + 1];
          for (Index b = a; b < c.column_start[t + 1]; ++b)
            {
              const double product = signs[t] * c.values[a] * c.values[b];
              const auto   found   = std::lower_bound(first, last, c.row_index[b]);
              if (found == last || *found != c.row_index[b])
                {
                  inside = inside && product == 0.;
                  continue;
                }
              const auto k = found - permuted_lower.row_index.begin();
              permuted_lower.values[k] += product;
              factored_values[k] += product;
              // C no longer holds what A held at the last load: the next load compares anew.
              if (!input_values.empty())
                input_values[source[k]] = std::numeric_limits<double>::quiet_NaN();
            }
        }
    return inside;
  }

  const sparse::CSCMatrix &PermutedMatrix::lower() const
  {
    return permuted_lower;
  }

  Index PermutedMatrix::n_nonzeros() const
  {
    return permuted_lower.n_nonzeros();
  }

  void PermutedMatrix::save(BinaryWriter &writer) const
  {
    writer.write(loaded);
    writer.write(permuted_lower.values);
    writer.write(factored_values);
  }

  void PermutedMatrix::load(BinaryReader &reader)
  {
    const auto          was_loaded = reader.get<bool>();
    std::vector<double> values;
    reader.read(values);
    if (values.size() != permuted_lower.values.size())
      reader.fail("the permuted matrix holds " + std::to_string(values.size()) +
                  " values, this analysis " + std::to_string(permuted_lower.values.size()));
    std::vector<double> factored;
    reader.read(factored);
    if (!factored.empty() && factored.size() != permuted_lower.values.size())
      reader.fail("the permuted matrix holds " + std::to_string(factored.size()) +
                  " factored values, this analysis " + std::to_string(permuted_lower.values.size()));
    loaded                = was_loaded;
    permuted_lower.values = std::move(values);
    factored_values       = std::move(factored);
    // A's values as last loaded, from C's (a mirror that differed within the symmetry
    // tolerance reads as changed at the next load, which changes no column of C).
    input_values.assign(entry_of_input.size(), 0.);
    for (std::size_t p = 0; p < entry_of_input.size(); ++p)
      input_values[p] = permuted_lower.values[entry_of_input[p]];
    if (!loaded)
      input_values.clear();
  }
} // namespace warpchol::cholesky
