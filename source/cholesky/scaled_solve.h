#pragma once

#include <warpchol/base/types.h>

#include <hwy/base.h>

/**
 * @file
 * (Private to the solver.) The preconditioner's low-precision copy of a supernodal factor
 * and its triangular solves with one right-hand side: the entries stored in 16 bits
 * (IEEE half) or 32, each column scaled by a power of two so that its largest entry is at
 * most 1 (half's range, 6e-8 to 65504, would otherwise lose the small entries of a stiff
 * body's factor or overflow on its large ones), the arithmetic in single precision.
 *
 * CG reads the preconditioner's factor twice per iteration (forward and backward): it is
 * the largest part of what an iteration moves, and half the bytes halve that part. The
 * kernels stream each supernode once per pass, eight columns at a time, without BLAS.
 */
namespace warpchol::cholesky
{
  /** An IEEE half-precision number (Highway's portable type). */
  using Half = hwy::float16_t;

  /** @p x rounded to the nearest half (ties to even; beyond the range: infinity). */
  Half  half_from_float(float x);
  float float_from_half(Half h);

  /**
   * The copy's layout, per supernode (nr rows, nc columns): its columns in blocks of
   * scaled_block_columns (the last may be narrower), each block stored from its diagonal
   * row down as tiles of scaled_tile_rows rows, one after the other; in a tile, column by
   * column. Block j0 of width B holds rows [j0, nr), padded with zeros to whole tiles, in
   * B * ceil((nr - j0) / scaled_tile_rows) * scaled_tile_rows entries. So the solves read
   * each block, and each supernode, as one stream (a column of a supernode is too short a
   * stream for the hardware's prefetchers), and need no code for a last partial tile.
   */
  constexpr Index scaled_block_columns = 8;
  constexpr Index scaled_tile_rows     = 8;

  /** The entries of a supernode of @p nr rows and @p nc columns in the copy's layout. */
  Index scaled_copy_entries(Index nr, Index nc);

  /**
   * Round the local columns [q, nc) of a supernode (nr rows, column-major, @p values in
   * double) into @p stored (the copy's layout, above): column j scaled by a power of two,
   * @p scale[j], so that its largest entry below the diagonal is at most 1 in size;
   * @p inverse_diagonal[j] = 1 / (L_jj / scale[j]) in single precision. The blocks that
   * hold those columns are written whole, entries above the diagonal and padding as 0.
   */
  void round_columns(const double *values, Index nr, Index nc, Index q, Half *stored, float *scale,
                     float *inverse_diagonal);
  void round_columns(const double *values, Index nr, Index nc, Index q, float *stored, float *scale,
                     float *inverse_diagonal);

  /**
   * Forward substitution on one supernode of a column-scaled factor (round_columns()):
   * @p work holds the supernode's nc entries of x, then nr - nc zeros, then
   * scaled_tile_rows zeros (the last tile's rows past nr, read and written whole). On
   * return its first nc entries are L11^-1 x, the next nr - nc are - L21 L11^-1 x, what
   * the rows below it subtract.
   */
  void forward_scaled(const Half *l, Index nr, Index nc, const float *scale, const float *inverse_diagonal,
                      float *work);
  void forward_scaled(const float *l, Index nr, Index nc, const float *scale, const float *inverse_diagonal,
                      float *work);

  /**
   * Backward substitution on one supernode: @p work holds its nc entries of x, then the
   * solution on the nr - nc rows below it, then scaled_tile_rows zeros (the last tile's
   * rows past nr); its first nc entries become L11^-T (x - L21^T below).
   */
  void backward_scaled(const Half *l, Index nr, Index nc, const float *scale, const float *inverse_diagonal,
                       float *work);
  void backward_scaled(const float *l, Index nr, Index nc, const float *scale, const float *inverse_diagonal,
                       float *work);
} // namespace warpchol::cholesky
