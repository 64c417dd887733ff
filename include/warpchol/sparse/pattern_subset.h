#pragma once

#include <warpchol/base/types.h>

#include <string>
#include <vector>

/**
 * @file
 * A matrix whose pattern is a subset of an analyzed one: the entries it leaves out are
 * zeros. Arithmetic drops explicit zeros (SciPy's A + D with a diagonal D, a product that
 * cancels), so a matrix with the values of the analyzed pattern may come back with fewer
 * entries; the solver takes it, as CHOLMOD does, and refuses only an entry outside.
 */
namespace warpchol::sparse
{
  /**
   * The places of the entries of a matrix among those of an analyzed pattern: places[k] is
   * the position in @p pattern_row of the matrix's entry k. Both are CSC arrays of @p n
   * columns (the pattern's trusted, the matrix's checked; @p subset_start holds n + 1
   * entries), rows within a column in any order. With @p transposed the matrix's arrays are those of a CSR matrix read as CSC,
   * and messages name its entries (row, column) as the user stores them.
   *
   * Throws MatrixError, naming the entry, for an entry outside the pattern or stored twice,
   * and for arrays that are not those of n columns (column starts that do not run from 0
   * to @p n_subset_entries or decrease, a row out of range). O(n + entries).
   */
  std::vector<Index> places_in_pattern(Index        n,
                                       const Index *pattern_start,
                                       const Index *pattern_row,
                                       const Index *subset_start,
                                       const Index *subset_row,
                                       Index        n_subset_entries,
                                       bool         transposed = false);

  /** "(i,j)": how a message names the entry in row @p i, column @p j. */
  std::string entry_name(Index i, Index j);

  /**
   * The one-line message for A(@p i,@p j) = @p value, not finite: "matrix entry A(3,1) is
   * NaN", "matrix entry A(3,1) is infinite (-inf)".
   */
  std::string non_finite_entry_message(Index i, Index j, double value);
} // namespace warpchol::sparse
