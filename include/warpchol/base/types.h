#pragma once

#include <cstdint>

/**
 * @file
 * Index and scalar types shared by the solver and the finite element code.
 */
namespace warpchol
{
  /**
   * Index of a row, a column or a stored entry. Signed 64 bits, as SuiteSparse_long: the
   * factor of a large 3D problem can hold more than 2^31 entries, and -1 serves as "none".
   */
  using Index = std::int64_t;
} // namespace warpchol
