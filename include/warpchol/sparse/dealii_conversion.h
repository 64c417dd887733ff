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
   * Copy the values of @p matrix into @p csc through @p map: O(nnz), one pass in storage
   * order, where copy_values() above searches each entry's place in its column. Throws MatrixError, naming an entry, if the pattern of
   * @p matrix is not the map's.
   */
  void copy_values(const dealii::SparseMatrix<double> &matrix, const DealiiCscMap &map, CSCMatrix &csc);

#ifdef DEAL_II_WITH_TRILINOS
  /**
   * Call @p visit(row, column, value) for each stored entry of @p matrix, with global row
   * and column numbers, in Epetra's order (its local rows in turn, the entries of a row as
   * Epetra stores them). Throws MatrixError unless this process holds every row.
   */
  template <typename Visit>
  void for_each_stored_entry(const dealii::TrilinosWrappers::SparseMatrix &matrix, const Visit &visit);

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

#ifdef DEAL_II_WITH_TRILINOS
#  include <warpchol/base/exceptions.h>

#  include <Epetra_CrsMatrix.h>

#  include <string>

namespace warpchol::sparse
{
  template <typename Visit>
  void for_each_stored_entry(const dealii::TrilinosWrappers::SparseMatrix &matrix, const Visit &visit)
  {
    const Epetra_CrsMatrix &epetra = matrix.trilinos_matrix();
    if (static_cast<dealii::types::global_dof_index>(epetra.NumMyRows()) != matrix.m())
      throw MatrixError("the Trilinos matrix has " + std::to_string(matrix.m()) + " rows, this process holds " +
                        std::to_string(epetra.NumMyRows()) + " of them");
    // The graph's maps: Epetra_CrsMatrix::RowMap() and ColMap() cast the graph's
    // Epetra_BlockMap to the Epetra_Map it is not (UndefinedBehaviorSanitizer: invalid
    // downcast); GID() is the block map's.
    const Epetra_BlockMap &row_map    = epetra.Graph().RowMap();
    const Epetra_BlockMap &column_map = epetra.Graph().ColMap();
    for (int row = 0; row < epetra.NumMyRows(); ++row)
      {
        int     n_entries = 0;
        double *values    = nullptr;
        int    *columns   = nullptr;
        epetra.ExtractMyRowView(row, n_entries, values, columns);
        const Index global_row = row_map.GID(row);
        for (int k = 0; k < n_entries; ++k)
          visit(global_row, static_cast<Index>(column_map.GID(columns[k])), values[k]);
      }
  }
} // namespace warpchol::sparse
#endif
