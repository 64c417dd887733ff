#pragma once

#include <warpchol/sparse/csc_matrix.h>

#include <deal.II/base/config.h>

#include <deal.II/lac/sparse_matrix.h>

#ifdef DEAL_II_WITH_TRILINOS
#  include <deal.II/lac/trilinos_sparse_matrix.h>
#endif

#include <vector>

/**
 * @file
 * From deal.II's matrices to the solver's formats.
 */
namespace warpchol::sparse
{
  /**
   * The CSC form (full storage) of a deal.II SparseMatrix: every entry of its sparsity
   * pattern is kept, explicit zeros included, so the pattern does not depend on values
   * and stays fixed from one assembly to the next.
   */
  CSCMatrix to_csc(const dealii::SparseMatrix<double> &matrix);

  /**
   * Copy the values of @p matrix into @p csc, which came from to_csc() of a matrix with
   * the same sparsity pattern: O(nnz), no allocation. Throws MatrixError, naming an
   * entry, if the patterns differ.
   */
  void copy_values(const dealii::SparseMatrix<double> &matrix, CSCMatrix &csc);

  /**
   * Where the stored entries of deal.II matrices of one sparsity pattern go in their CSC
   * form, found once (csc_map()), so that copy_values() below copies the values of each
   * next matrix without a search.
   */
  struct DealiiCscMap
  {
    /**
     * The pattern the map was made for, as deal.II stores it (row by row, the diagonal
     * first in each): where each row's entries start, and their columns. copy_values()
     * checks a matrix's pattern against it.
     */
    std::vector<Index>                           row_start;
    std::vector<dealii::types::global_dof_index> column;
    /** position[k]: where the k-th stored entry goes in the CSC form. */
    std::vector<Index> position;
  };

  /**
   * The map from the storage of @p matrix to @p csc, which came from to_csc() of a matrix
   * with the same pattern. Throws MatrixError for an entry that @p csc lacks.
   */
  DealiiCscMap csc_map(const dealii::SparseMatrix<double> &matrix, const CSCMatrix &csc);

  /**
   * Copy the values of @p matrix into @p csc through @p map: O(nnz), no search, 2.5x faster
   * than copy_values() above. Throws MatrixError, naming an entry, if the pattern of
   * @p matrix is not the map's.
   */
  void copy_values(const dealii::SparseMatrix<double> &matrix, const DealiiCscMap &map, CSCMatrix &csc);

#ifdef DEAL_II_WITH_TRILINOS
  /**
   * The CSC form (full storage) of a Trilinos matrix whose rows are all held by this
   * process: every stored entry is kept, explicit zeros included. Throws MatrixError if
   * the process holds only some of the rows.
   */
  CSCMatrix to_csc(const dealii::TrilinosWrappers::SparseMatrix &matrix);

  /**
   * For each stored entry of @p matrix in Epetra's order (local rows in turn, the entries
   * of a row as Epetra stores them), its position in @p csc, which came from to_csc() of
   * a matrix with the same pattern. Throws MatrixError for an entry that @p csc lacks.
   */
  std::vector<Index> csc_positions(const dealii::TrilinosWrappers::SparseMatrix &matrix, const CSCMatrix &csc);

  /**
   * Copy the values of @p matrix into @p csc at the @p positions that csc_positions()
   * computed for a matrix of the same pattern: O(nnz), no search. Throws MatrixError,
   * naming an entry, if the patterns differ.
   */
  void copy_values(const dealii::TrilinosWrappers::SparseMatrix &matrix,
                   const std::vector<Index>                     &positions,
                   CSCMatrix                                    &csc);
#endif
} // namespace warpchol::sparse
