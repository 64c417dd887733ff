#pragma once

/**
 * @file
 * (Private to the solver.) The triangular solves of one supernode of the double factor with
 * one right-hand side, without BLAS: a direct solve (the partial strategy's step, a
 * contact's correction) walks every supernode twice, most of them a few columns wide, and
 * a BLAS call's set-up per supernode (dtrsv, then dgemv) costs more than its arithmetic.
 * The kernels stream each supernode's columns a block at a time, on the element family's
 * SIMD target (scaled_solve.h does the same for the preconditioner's low-precision copy).
 */

#include <warpchol/base/types.h>
#include <warpchol/cholesky/supernodal_symbolic.h>

#include <vector>

namespace warpchol::cholesky
{
  /**
   * Forward substitution on one supernode (@p l: nr rows, nc columns, column-major, its
   * diagonal block on top). @p work holds the supernode's nc entries of x, then nr - nc
   * zeros; on return its first nc entries are L11^-1 x and the next nr - nc are
   * - L21 L11^-1 x, what the rows below subtract.
   */
  void forward_supernode_double(const double *l, Index nr, Index nc, double *work);

  /**
   * forward_supernode_double() on supernode @p s of the factor @p values, for the whole
   * vector @p x (n entries): x's entries of s become L11^-1 x_s, and @p work's entries
   * [nc, nr) hold - L21 L11^-1 x_s, which the caller adds to x's rows below (s's rows from
   * its nc-th on), or routes elsewhere.
   */
  void forward_supernode_gathered(const SupernodalSymbolic &symbolic, const double *values, Index s, double *x,
                                  std::vector<double> &work);

  /**
   * Backward substitution on one supernode: @p work holds its nc entries of x, then the
   * solution on its nr - nc rows below; its first nc entries become L11^-T (x - L21^T below).
   */
  void backward_supernode_double(const double *l, Index nr, Index nc, double *work);
} // namespace warpchol::cholesky
