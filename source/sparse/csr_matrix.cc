#include <warpchol/sparse/csr_matrix.h>

namespace warpchol::sparse
{
  Index CSRMatrix::n_nonzeros() const
  {
    return row_start.empty() ? 0 : row_start.back();
  }

  void CSRMatrix::vmult(const double *x, double *y) const
  {
    for (Index i = 0; i < n_rows; ++i)
      {
        double sum = 0.;
        for (Index k = row_start[i]; k < row_start[i + 1]; ++k)
          sum += values[k] * x[column_index[k]];
        y[i] = sum;
      }
  }
} // namespace warpchol::sparse
