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
 * kernels stream each supernode's columns once per pass, four at a time, without BLAS.
 */
namespace warpchol::cholesky
{
  /** An IEEE half-precision number (Highway's portable type). */
  using Half = hwy::float16_t;

  /**
   * Entries of padding the kernels need after the copy's values, after x and after the
   * buffer of the rows below a supernode: they read whole vectors past the last rows
   * (and write back only the rows). The copy's padding must hold zeros.
   */
  constexpr Index scaled_solve_padding = 64;

  /** @p x rounded to the nearest half (ties to even; beyond the range: infinity). */
  Half  half_from_float(float x);
  float float_from_half(Half h);

  /**
   * Round the local columns [q, nc) of a supernode (nr rows, column-major, @p values in
   * double) into @p stored (the same layout): column j scaled by a power of two,
   * @p scale[j], so that its largest entry below the diagonal is at most 1 in size;
   * @p inverse_diagonal[j] = 1 / (L_jj / scale[j]) in single precision. Entries above
   * the diagonal are written as 0.
   */
  void round_columns(const double *values, Index nr, Index nc, Index q, Half *stored, float *scale,
                     float *inverse_diagonal);
  void round_columns(const double *values, Index nr, Index nc, Index q, float *stored, float *scale,
                     float *inverse_diagonal);

  /**
   * Forward substitution on one supernode of a column-scaled factor (round_columns()):
   * @p own (its nc columns' entries of x) becomes L11^-1 own, and @p below (nr - nc
   * entries) is set to - L21 own, what the rows below it subtract.
   */
  void forward_scaled(const Half *l, Index nr, Index nc, const float *scale, const float *inverse_diagonal,
                      float *own, float *below);
  void forward_scaled(const float *l, Index nr, Index nc, const float *scale, const float *inverse_diagonal,
                      float *own, float *below);

  /**
   * Backward substitution on one supernode: @p own becomes L11^-T (own - L21^T below),
   * @p below holding the solution on the rows below it.
   */
  void backward_scaled(const Half *l, Index nr, Index nc, const float *scale, const float *inverse_diagonal,
                       float *own, const float *below);
  void backward_scaled(const float *l, Index nr, Index nc, const float *scale, const float *inverse_diagonal,
                       float *own, const float *below);
} // namespace warpchol::cholesky
