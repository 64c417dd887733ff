#pragma once

/**
 * @file
 * (Private to contact.) The kernel of Gauss-Seidel's product W lambda
 * (ContactCompliance::Product): when one contact's impulse changes by delta, three columns
 * of W (or of the Gram matrix of a factored W) times delta are added to the product. It is
 * the inner loop of every Gauss-Seidel sweep, so it runs on the element family's SIMD
 * target (base/simd.h) rather than the library's plain SSE2.
 */

#include <cstddef>

namespace warpchol::fem
{
  /**
   * y[i] += c0[i] t[0] + c1[i] t[1] + c2[i] t[2] for i < @p length, where c0, c1 and c2 are
   * the three columns of @p length entries that start at @p columns.
   */
  void add_three_columns(const double *columns, std::size_t length, const double (&t)[3], double *y);
} // namespace warpchol::fem
