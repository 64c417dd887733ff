#include <warpchol/base/exceptions.h>
#include <warpchol/sparse/conversions.h>
#include <warpchol/sparse/dealii_conversion.h>

#include <algorithm>

namespace warpchol::sparse
{
  CSCMatrix to_csc(const dealii::SparseMatrix<double> &matrix)
  {
    // deal.II stores rows, diagonal first: gather them as CSR with sorted columns, then
    // transpose (a counting sort) into CSC.
    CSRMatrix rows;
    rows.n_rows = matrix.m();
    rows.n_cols = matrix.n();
    rows.row_start.assign(rows.n_rows + 1, 0);
    rows.column_index.reserve(matrix.n_nonzero_elements());
    rows.values.reserve(matrix.n_nonzero_elements());
    std::vector<std::pair<Index, double>> row_entries;
    for (Index i = 0; i < rows.n_rows; ++i)
      {
        row_entries.clear();
        for (auto entry = matrix.begin(i); entry != matrix.end(i); ++entry)
          row_entries.emplace_back(entry->column(), entry->value());
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

  void copy_values(const dealii::SparseMatrix<double> &matrix, CSCMatrix &csc)
  {
    if (static_cast<Index>(matrix.m()) != csc.n_rows || static_cast<Index>(matrix.n()) != csc.n_cols ||
        static_cast<Index>(matrix.n_nonzero_elements()) != csc.n_nonzeros())
      throw MatrixError("copy_values: the CSC matrix does not have the deal.II matrix's pattern");
    // Column j of the CSC form lists its rows increasingly; visiting the deal.II rows in
    // increasing order therefore meets the entries of column j in storage order, whatever
    // the order of the entries within a row (deal.II puts the diagonal first).
    std::vector<Index> cursor(csc.column_start.begin(), csc.column_start.end() - 1);
    for (Index i = 0; i < csc.n_rows; ++i)
      for (auto entry = matrix.begin(i); entry != matrix.end(i); ++entry)
        csc.values[cursor[entry->column()]++] = entry->value();
  }
} // namespace warpchol::sparse
