#include <warpchol/base/exceptions.h>
#include <warpchol/sparse/csc_matrix.h>

#include <algorithm>
#include <string>

namespace warpchol::sparse
{
  CSCMatrix CSCMatrix::zero(const Index n_rows, const Index n_cols, const Storage storage)
  {
    CSCMatrix matrix;
    matrix.n_rows  = n_rows;
    matrix.n_cols  = n_cols;
    matrix.storage = storage;
    matrix.column_start.assign(n_cols + 1, 0);
    return matrix;
  }

  Index CSCMatrix::n_nonzeros() const
  {
    return column_start.empty() ? 0 : column_start.back();
  }

  double CSCMatrix::operator()(Index i, Index j) const
  {
    if (storage == Storage::lower && i < j)
      std::swap(i, j);
    const auto first = row_index.begin() + column_start[j];
    const auto last  = row_index.begin() + column_start[j + 1];
    const auto found = std::lower_bound(first, last, i);
    return (found != last && *found == i) ? values[found - row_index.begin()] : 0.;
  }

  void CSCMatrix::vmult(const double *x, double *y) const
  {
    std::fill(y, y + n_rows, 0.);
    for (Index j = 0; j < n_cols; ++j)
      for (Index k = column_start[j]; k < column_start[j + 1]; ++k)
        {
          const Index i = row_index[k];
          y[i] += values[k] * x[j];
          if (storage == Storage::lower && i != j)
            y[j] += values[k] * x[i];
        }
  }

  void CSCMatrix::check_consistency() const
  {
    auto fail = [](const std::string &what) { throw MatrixError("invalid CSC matrix: " + what); };
    if (n_rows < 0 || n_cols < 0)
      fail("negative size");
    if (static_cast<Index>(column_start.size()) != n_cols + 1)
      fail("column_start has " + std::to_string(column_start.size()) + " entries, expected " +
           std::to_string(n_cols + 1));
    if (column_start.front() != 0)
      fail("column_start[0] is not 0");
    if (static_cast<Index>(row_index.size()) != n_nonzeros() ||
        static_cast<Index>(values.size()) != n_nonzeros())
      fail("row_index/values do not hold column_start[n] entries");
    for (Index j = 0; j < n_cols; ++j)
      {
        if (column_start[j + 1] < column_start[j])
          fail("column_start decreases at column " + std::to_string(j));
        for (Index k = column_start[j]; k < column_start[j + 1]; ++k)
          {
            const Index i = row_index[k];
            if (i < 0 || i >= n_rows)
              fail("row index " + std::to_string(i) + " out of range in column " +
                   std::to_string(j));
            if (k > column_start[j] && row_index[k - 1] >= i)
              fail("row indices of column " + std::to_string(j) + " not sorted or repeated");
            if (storage == Storage::lower && i < j)
              fail("entry (" + std::to_string(i) + "," + std::to_string(j) +
                   ") above the diagonal of a lower-stored matrix");
          }
      }
  }
} // namespace warpchol::sparse
