#pragma once

#include <warpchol/base/types.h>
#include <warpchol/cholesky/symbolic.h>

#include <vector>

/**
 * @file
 * Triangular solves with a simplicial factor (CHOLMOD's "solve" concern).
 */
namespace warpchol::cholesky
{
  /**
   * Overwrite the @p n_rhs right-hand sides in @p y (column-major, leading dimension n)
   * with the solutions of L L^T z = y, L given by @p symbolic and @p l_values.
   */
  void solve_simplicial(const SymbolicFactorization &symbolic,
                        const std::vector<double>   &l_values,
                        double                      *y,
                        Index                        n_rhs);
} // namespace warpchol::cholesky
