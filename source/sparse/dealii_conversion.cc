#include <warpchol/base/exceptions.h>
#include <warpchol/sparse/conversions.h>
#include <warpchol/sparse/dealii_conversion.h>

#include <algorithm>
#include <string>
#include <utility>

namespace warpchol::sparse
{
  namespace
  {
    /** The one-line error of an entry (@p row, @p column) that is not where the pattern has it. */
    MatrixError not_in_pattern(const char *source, const Index row, const Index column)
    {
      return MatrixError("copy_values: entry (" + std::to_string(row) + "," + std::to_string(column) + ") of the " +
                         std::string(source) + " is not in the pattern of the CSC matrix");
    }

    /**
     * Where the entry (@p row, @p column) of a matrix of @p source lies in @p csc: by a
     * search, or (@p position >= 0, computed before) checked to be there.
     */
    Index csc_position(const CSCMatrix &csc, const char *source, const Index row, const Index column,
                       const Index position = -1)
    {
      if (column < 0 || column >= csc.n_cols)
        throw not_in_pattern(source, row, column);
      const Index begin = csc.column_start[column], end = csc.column_start[column + 1];
      if (position >= 0)
        {
          if (position < begin || position >= end || csc.row_index[position] != row)
            throw not_in_pattern(source, row, column);
          return position;
        }
      const auto found = std::lower_bound(csc.row_index.begin() + begin, csc.row_index.begin() + end, row);
      if (found == csc.row_index.begin() + end || *found != row)
        throw not_in_pattern(source, row, column);
      return found - csc.row_index.begin();
    }

    /** The error of a matrix whose size or number of entries is not the CSC form's. */
    MatrixError other_size(const char *source, const Index n_rows, const Index n_cols, const Index n_entries,
                           const CSCMatrix &csc)
    {
      return MatrixError("copy_values: the " + std::string(source) + " (" + std::to_string(n_rows) + "x" + std::to_string(n_cols) +
                         ", " + std::to_string(n_entries) + " entries) does not have the pattern of the CSC matrix (" +
                         std::to_string(csc.n_rows) + "x" + std::to_string(csc.n_cols) + ", " +
                         std::to_string(csc.n_nonzeros()) + " entries)");
    }

    /**
     * Row by row, as (column, value) pairs that @p entries_of_row(i, add) hands to add,
     * to CSC: each row sorted by column, then transposed (a counting sort).
     */
    template <typename EntriesOfRow>
    CSCMatrix rows_to_csc(const Index n_rows, const Index n_cols, const Index n_entries,
                          const EntriesOfRow &entries_of_row)
    {
      CSRMatrix rows;
      rows.n_rows = n_rows;
      rows.n_cols = n_cols;
      rows.row_start.assign(n_rows + 1, 0);
      rows.column_index.reserve(n_entries);
      rows.values.reserve(n_entries);
      std::vector<std::pair<Index, double>> row_entries;
      for (Index i = 0; i < n_rows; ++i)
        {
          row_entries.clear();
          entries_of_row(i, [&](const Index column, const double value) { row_entries.emplace_back(column, value); });
          std::sort(row_entries.begin(), row_entries.end());
          for (const auto &[column, value] : row_entries)
            {
              rows.column_index.push_back(column);
              rows.values.push_back(value);
            }
          rows.row_start[i + 1] = static_cast<Index>(rows.column_index.size());
        }
      return sparse::to_csc(rows);
    }
  } // namespace

  CSCMatrix to_csc(const dealii::SparseMatrix<double> &matrix)
  {
    // deal.II stores rows, diagonal first.
    return rows_to_csc(matrix.m(), matrix.n(), matrix.n_nonzero_elements(), [&](const Index i, const auto &add) {
      for (auto entry = matrix.begin(i); entry != matrix.end(i); ++entry)
        add(entry->column(), entry->value());
    });
  }

  void copy_values(const dealii::SparseMatrix<double> &matrix, CSCMatrix &csc)
  {
    if (static_cast<Index>(matrix.m()) != csc.n_rows || static_cast<Index>(matrix.n()) != csc.n_cols ||
        static_cast<Index>(matrix.n_nonzero_elements()) != csc.n_nonzeros())
      throw other_size("deal.II matrix", matrix.m(), matrix.n(), matrix.n_nonzero_elements(), csc);
    // Column j of the CSC form lists its rows increasingly; visiting the deal.II rows in
    // increasing order therefore meets the entries of column j in storage order, whatever
    // the order of the entries within a row (deal.II puts the diagonal first). That the
    // entry met is the one stored there checks the pattern on the way.
    std::vector<Index> cursor(csc.column_start.begin(), csc.column_start.end() - 1);
    for (Index i = 0; i < csc.n_rows; ++i)
      {
        const auto end = matrix.end(i);
        for (auto entry = matrix.begin(i); entry != end; ++entry)
          {
            const Index j = entry->column();
            csc.values[csc_position(csc, "deal.II matrix", i, j, j < csc.n_cols ? cursor[j]++ : 0)] = entry->value();
          }
      }
  }

  DealiiCscMap csc_map(const dealii::SparseMatrix<double> &matrix, const CSCMatrix &csc)
  {
    DealiiCscMap map;
    map.row_start.reserve(matrix.m() + 1);
    map.row_start.push_back(0);
    map.column.reserve(matrix.n_nonzero_elements());
    map.position.reserve(matrix.n_nonzero_elements());
    for (Index i = 0; i < static_cast<Index>(matrix.m()); ++i)
      {
        for (auto entry = matrix.begin(i); entry != matrix.end(i); ++entry)
          {
            map.column.push_back(entry->column());
            map.position.push_back(csc_position(csc, "deal.II matrix", i, entry->column()));
          }
        map.row_start.push_back(map.column.size());
      }
    return map;
  }

  void copy_values(const dealii::SparseMatrix<double> &matrix, const DealiiCscMap &map, CSCMatrix &csc)
  {
    if (static_cast<Index>(matrix.m()) != csc.n_rows || static_cast<Index>(matrix.n()) != csc.n_cols ||
        static_cast<Index>(matrix.n_nonzero_elements()) != csc.n_nonzeros() ||
        static_cast<Index>(map.position.size()) != csc.n_nonzeros() ||
        static_cast<Index>(map.row_start.size()) != csc.n_rows + 1)
      throw other_size("deal.II matrix", matrix.m(), matrix.n(), matrix.n_nonzero_elements(), csc);
    Index k = 0;
    for (Index i = 0; i < csc.n_rows; ++i)
      {
        // deal.II's end(row) is not inlined: once per row.
        const auto end = matrix.end(i);
        for (auto entry = matrix.begin(i); entry != end; ++entry, ++k)
          {
            if (k >= map.row_start[i + 1] || entry->column() != map.column[k])
              throw not_in_pattern("deal.II matrix", i, entry->column());
            csc.values[map.position[k]] = entry->value();
          }
        if (k != map.row_start[i + 1])
          throw MatrixError("copy_values: row " + std::to_string(i) + " of the deal.II matrix has " +
                            std::to_string(matrix.get_row_length(i)) + " entries, the CSC matrix's pattern " +
                            std::to_string(map.row_start[i + 1] - map.row_start[i]));
      }
  }

#ifdef DEAL_II_WITH_TRILINOS

  CSCMatrix to_csc(const dealii::TrilinosWrappers::SparseMatrix &matrix)
  {
    // Epetra numbers its local rows in the order of its row map: gather them by global row.
    std::vector<std::vector<std::pair<Index, double>>> row_entries(matrix.m());
    for_each_stored_entry(matrix, [&](const Index row, const Index column, const double value) {
      row_entries[row].emplace_back(column, value);
    });
    return rows_to_csc(matrix.m(), matrix.n(), matrix.n_nonzero_elements(), [&](const Index i, const auto &add) {
      for (const auto &[column, value] : row_entries[i])
        add(column, value);
    });
  }

  std::vector<Index> csc_positions(const dealii::TrilinosWrappers::SparseMatrix &matrix, const CSCMatrix &csc)
  {
    std::vector<Index> positions;
    positions.reserve(csc.n_nonzeros());
    for_each_stored_entry(matrix, [&](const Index row, const Index column, double) {
      positions.push_back(csc_position(csc, "Trilinos matrix", row, column));
    });
    return positions;
  }

  void copy_values(const dealii::TrilinosWrappers::SparseMatrix &matrix,
                   const std::vector<Index>                     &positions,
                   CSCMatrix                                    &csc)
  {
    if (static_cast<Index>(matrix.n_nonzero_elements()) != csc.n_nonzeros() ||
        static_cast<Index>(positions.size()) != csc.n_nonzeros() || static_cast<Index>(matrix.m()) != csc.n_rows ||
        static_cast<Index>(matrix.n()) != csc.n_cols)
      throw other_size("Trilinos matrix", matrix.m(), matrix.n(), matrix.n_nonzero_elements(), csc);
    std::size_t k = 0;
    for_each_stored_entry(matrix, [&](const Index row, const Index column, const double value) {
      csc.values[csc_position(csc, "Trilinos matrix", row, column, positions[k++])] = value;
    });
  }
#endif
} // namespace warpchol::sparse
