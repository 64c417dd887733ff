#pragma once

#include <warpchol/base/types.h>
#include <warpchol/cholesky/permuted_matrix.h>
#include <warpchol/sparse/csc_matrix.h>

#include <vector>

/**
 * @file
 * A change of the factored matrix written as the update and downdate take it:
 * Delta = C diag(signs) C^T, C sparse, each column on one elimination-tree path.
 */
namespace warpchol::cholesky
{
  /** Delta = C diag(signs) C^T: C n x k (permuted rows, sorted), signs +1 or -1. */
  struct LowRankChange
  {
    sparse::CSCMatrix   c;
    std::vector<double> signs;
  };

  /**
   * The low-rank form of the symmetric change whose lower-triangle entries are
   * @p changes (permuted numbering, each entry once), found without knowing where it came
   * from (a grasp's springs, a cut's elements, re-rotated elements).
   *
   * On the set S of rows and columns it touches, Delta = G D G^T - E, an LDL^T in the
   * elimination order: the column of G at row i has the structure of that row's column
   * in the Cholesky factor of Delta, within L's (a change of A's entries fills nothing
   * L does not hold), so every column of C lies on one path. Pivots too small for the
   * column below them (the change is indefinite, or semidefinite like a stiffness without
   * its rigid motions) are raised, as in Gill, Murray and Wright's modified Cholesky, so
   * that no entry of G exceeds the change's own scale; each raise e is given back by a
   * column sqrt(|e|) e_i of the opposite sign (E). The rank is |S| plus the raised pivots,
   * less the columns that vanish: a grasp of v vertices (a diagonal change) gives 3v unit
   * columns; a cut, the touched vertices' dofs, however many elements share them.
   */
  LowRankChange low_rank_form(Index n, const std::vector<PermutedMatrix::Change> &changes);

  /** The rows and columns @p changes touch (permuted, sorted): S above. */
  std::vector<Index> touched_rows(const std::vector<PermutedMatrix::Change> &changes);
} // namespace warpchol::cholesky
