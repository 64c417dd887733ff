#include <warpchol/sparse/bsc_matrix.h>

#include <algorithm>

namespace warpchol::sparse
{
  Index BSCMatrix::n_blocks() const
  {
    return block_column_start.empty() ? 0 : block_column_start.back();
  }

  void BSCMatrix::vmult(const double *x, double *y) const
  {
    std::fill(y, y + block_size * n_block_rows, 0.);
    for (Index J = 0; J < n_block_cols; ++J)
      for (Index k = block_column_start[J]; k < block_column_start[J + 1]; ++k)
        {
          const Block3 &block = blocks[k];
          double       *y_I   = y + block_size * block_row_index[k];
          const double *x_J   = x + block_size * J;
          for (int c = 0; c < block_size; ++c)
            for (int r = 0; r < block_size; ++r)
              y_I[r] += block[r + block_size * c] * x_J[c];
        }
  }
} // namespace warpchol::sparse
