#pragma once

#include <warpchol/base/types.h>

#include <array>
#include <vector>

/**
 * @file
 * Block Sparse Column storage with 3x3 blocks: one block per pair of mesh vertices, the
 * format SOFA's linear solvers use for 3D elasticity.
 */
namespace warpchol::sparse
{
  /** A dense 3x3 block, stored column by column. */
  using Block3 = std::array<double, 9>;

  /**
   * A sparse matrix of 3x3 blocks in compressed column form: the blocks of block column J
   * are block_row_index[k], blocks[k] for k in [block_column_start[J],
   * block_column_start[J+1]), block rows sorted.
   */
  struct BSCMatrix
  {
    static constexpr int block_size = 3;

    Index               n_block_rows = 0;
    Index               n_block_cols = 0;
    std::vector<Index>  block_column_start{0};
    std::vector<Index>  block_row_index;
    std::vector<Block3> blocks;

    /** Number of stored blocks. */
    Index n_blocks() const;

    /** y = A x, with x and y of size 3 n_block_cols and 3 n_block_rows. */
    void vmult(const double *x, double *y) const;
  };
} // namespace warpchol::sparse
