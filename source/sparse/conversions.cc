#include <warpchol/base/exceptions.h>
#include <warpchol/sparse/conversions.h>

#include <algorithm>

namespace warpchol::sparse
{
  namespace
  {
    /**
     * Transpose of a compressed structure: given the entries of n_major rows (or columns)
     * with their minor indices, return the compressed structure by minor index. Counting
     * sort, so the output indices come out sorted.
     */
    void transpose_structure(const Index               n_major,
                             const Index               n_minor,
                             const std::vector<Index> &major_start,
                             const std::vector<Index> &minor_index,
                             const std::vector<double> &values,
                             std::vector<Index>        &out_start,
                             std::vector<Index>        &out_index,
                             std::vector<double>       &out_values)
    {
      out_start.assign(n_minor + 1, 0);
      for (const Index m : minor_index)
        ++out_start[m + 1];
      for (Index m = 0; m < n_minor; ++m)
        out_start[m + 1] += out_start[m];
      out_index.resize(minor_index.size());
      out_values.resize(values.size());
      std::vector<Index> next(out_start.begin(), out_start.end() - 1);
      for (Index major = 0; major < n_major; ++major)
        for (Index k = major_start[major]; k < major_start[major + 1]; ++k)
          {
            const Index position  = next[minor_index[k]]++;
            out_index[position]   = major;
            out_values[position]  = values[k];
          }
    }
  } // namespace

  CSCMatrix transpose(const CSCMatrix &matrix)
  {
    if (matrix.storage == Storage::lower)
      return to_full_storage(matrix); // a symmetric matrix is its own transpose
    CSCMatrix result;
    result.n_rows  = matrix.n_cols;
    result.n_cols  = matrix.n_rows;
    result.storage = Storage::full;
    transpose_structure(matrix.n_cols, matrix.n_rows, matrix.column_start, matrix.row_index,
                        matrix.values, result.column_start, result.row_index, result.values);
    return result;
  }

  CSRMatrix to_csr(const CSCMatrix &matrix)
  {
    const CSCMatrix full = to_full_storage(matrix);
    CSRMatrix       result;
    result.n_rows = full.n_rows;
    result.n_cols = full.n_cols;
    transpose_structure(full.n_cols, full.n_rows, full.column_start, full.row_index,
                        full.values, result.row_start, result.column_index, result.values);
    return result;
  }

  CSCMatrix to_csc(const CSRMatrix &matrix)
  {
    CSCMatrix result;
    result.n_rows  = matrix.n_rows;
    result.n_cols  = matrix.n_cols;
    result.storage = Storage::full;
    transpose_structure(matrix.n_rows, matrix.n_cols, matrix.row_start, matrix.column_index,
                        matrix.values, result.column_start, result.row_index, result.values);
    return result;
  }

  CSCMatrix to_full_storage(const CSCMatrix &matrix)
  {
    if (matrix.storage == Storage::full)
      return matrix;
    // Count, per column, the stored lower entries plus the mirrored strictly-lower ones.
    CSCMatrix result = CSCMatrix::zero(matrix.n_rows, matrix.n_cols, Storage::full);
    for (Index j = 0; j < matrix.n_cols; ++j)
      for (Index k = matrix.column_start[j]; k < matrix.column_start[j + 1]; ++k)
        {
          ++result.column_start[j + 1];
          if (matrix.row_index[k] != j)
            ++result.column_start[matrix.row_index[k] + 1];
        }
    for (Index j = 0; j < matrix.n_cols; ++j)
      result.column_start[j + 1] += result.column_start[j];
    result.row_index.resize(result.column_start.back());
    result.values.resize(result.column_start.back());
    std::vector<Index> next(result.column_start.begin(), result.column_start.end() - 1);
    // Visiting columns in order fills column j with its mirrored entries (rows < j, from
    // earlier columns) before its own lower entries, so rows come out sorted.
    for (Index j = 0; j < matrix.n_cols; ++j)
      for (Index k = matrix.column_start[j]; k < matrix.column_start[j + 1]; ++k)
        {
          const Index i = matrix.row_index[k];
          Index       p = next[j]++;
          result.row_index[p] = i;
          result.values[p]    = matrix.values[k];
          if (i != j)
            {
              p                   = next[i]++;
              result.row_index[p] = j;
              result.values[p]    = matrix.values[k];
            }
        }
    return result;
  }

  CSCMatrix upper_triangle(const CSCMatrix &lower)
  {
    if (lower.storage != Storage::lower)
      throw MatrixError("upper_triangle() needs a matrix with lower storage");
    CSCMatrix upper;
    upper.n_rows  = lower.n_cols;
    upper.n_cols  = lower.n_rows;
    upper.storage = Storage::full;
    transpose_structure(lower.n_cols, lower.n_rows, lower.column_start, lower.row_index, lower.values,
                        upper.column_start, upper.row_index, upper.values);
    return upper;
  }

  CSCMatrix lower_triangle(const CSCMatrix &matrix)
  {
    if (matrix.storage == Storage::lower)
      return matrix;
    CSCMatrix result = CSCMatrix::zero(matrix.n_rows, matrix.n_cols, Storage::lower);
    for (Index j = 0; j < matrix.n_cols; ++j)
      {
        for (Index k = matrix.column_start[j]; k < matrix.column_start[j + 1]; ++k)
          if (matrix.row_index[k] >= j)
            {
              result.row_index.push_back(matrix.row_index[k]);
              result.values.push_back(matrix.values[k]);
            }
        result.column_start[j + 1] = static_cast<Index>(result.row_index.size());
      }
    return result;
  }

  BSCMatrix to_bsc(const CSCMatrix &matrix)
  {
    constexpr int b = BSCMatrix::block_size;
    if (matrix.n_rows % b != 0 || matrix.n_cols % b != 0)
      throw MatrixError("cannot convert a " + std::to_string(matrix.n_rows) + "x" +
                        std::to_string(matrix.n_cols) +
                        " matrix to 3x3 blocks: size is not a multiple of 3");
    const CSCMatrix full = to_full_storage(matrix);
    BSCMatrix       result;
    result.n_block_rows = full.n_rows / b;
    result.n_block_cols = full.n_cols / b;
    result.block_column_start.assign(result.n_block_cols + 1, 0);
    std::vector<Index> block_position(result.n_block_rows, -1);
    for (Index J = 0; J < result.n_block_cols; ++J)
      {
        const Index first_block = static_cast<Index>(result.blocks.size());
        std::vector<Index> rows_of_column;
        for (int c = 0; c < b; ++c)
          for (Index k = full.column_start[b * J + c]; k < full.column_start[b * J + c + 1]; ++k)
            {
              const Index I = full.row_index[k] / b;
              if (block_position[I] < 0)
                {
                  block_position[I] = 0;
                  rows_of_column.push_back(I);
                }
            }
        std::sort(rows_of_column.begin(), rows_of_column.end());
        for (const Index I : rows_of_column)
          {
            block_position[I] = static_cast<Index>(result.blocks.size());
            result.block_row_index.push_back(I);
            result.blocks.push_back(Block3{});
          }
        for (int c = 0; c < b; ++c)
          for (Index k = full.column_start[b * J + c]; k < full.column_start[b * J + c + 1]; ++k)
            {
              const Index i = full.row_index[k];
              result.blocks[block_position[i / b]][i % b + b * c] = full.values[k];
            }
        for (Index k = first_block; k < static_cast<Index>(result.blocks.size()); ++k)
          block_position[result.block_row_index[k]] = -1;
        result.block_column_start[J + 1] = static_cast<Index>(result.blocks.size());
      }
    return result;
  }

  CSCMatrix to_csc(const BSCMatrix &matrix)
  {
    constexpr int b = BSCMatrix::block_size;
    CSCMatrix result = CSCMatrix::zero(b * matrix.n_block_rows, b * matrix.n_block_cols);
    for (Index J = 0; J < matrix.n_block_cols; ++J)
      for (int c = 0; c < b; ++c)
        {
          for (Index k = matrix.block_column_start[J]; k < matrix.block_column_start[J + 1]; ++k)
            for (int r = 0; r < b; ++r)
              {
                result.row_index.push_back(b * matrix.block_row_index[k] + r);
                result.values.push_back(matrix.blocks[k][r + b * c]);
              }
          result.column_start[b * J + c + 1] = static_cast<Index>(result.row_index.size());
        }
    return result;
  }
} // namespace warpchol::sparse
