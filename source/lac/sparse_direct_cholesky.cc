#include <warpchol/base/exceptions.h>
#include <warpchol/lac/sparse_direct_cholesky.h>
#include <warpchol/sparse/dealii_conversion.h>

#include <deal.II/base/mpi.h>

namespace warpchol
{
  SparseDirectCholesky::AdditionalData::AdditionalData(const cholesky::OrderingMethod      ordering,
                                                       const cholesky::FactorizationMethod method,
                                                       const unsigned int                  n_threads)
    : ordering(ordering)
    , method(method)
    , n_threads(n_threads)
  {}

  SparseDirectCholesky::SparseDirectCholesky() = default;

  namespace
  {
    cholesky::SparseCholesky::Settings solver_settings(const SparseDirectCholesky::AdditionalData &additional_data)
    {
      cholesky::SparseCholesky::Settings settings;
      settings.ordering.method = additional_data.ordering;
      settings.method          = additional_data.method;
      settings.n_threads       = additional_data.n_threads;
      return settings;
    }
  } // namespace

  template <typename Work>
  void SparseDirectCholesky::factor_and_translate_errors(const Work &numeric_work)
  {
    // The solver's errors carry one line already; they become the deal.II exceptions of
    // this class, thrown as AssertThrow throws (with the file and line of this call).
    try
      {
        numeric_work();
      }
    catch (const NotPositiveDefinite &error)
      {
        AssertThrow(false, ExcNotPositiveDefinite(error.column, error.pivot));
      }
    catch (const Error &error)
      {
        AssertThrow(false, ExcInvalidMatrix(error.what()));
      }
  }

  void SparseDirectCholesky::assert_initialized() const
  {
    AssertThrow(cholesky_solver.state() != cholesky::SparseCholesky::State::empty, ExcNotInitialized());
  }

  void SparseDirectCholesky::assert_factored() const
  {
    AssertThrow(cholesky_solver.state() == cholesky::SparseCholesky::State::factorized, ExcNotInitialized());
  }

  std::vector<Index> SparseDirectCholesky::checked_rows(const std::vector<size_type> &changed_rows) const
  {
    std::vector<Index> rows(changed_rows.begin(), changed_rows.end());
    for (const size_type row : changed_rows)
      AssertThrow(row < n(), ExcRowOutOfRange(row, n()));
    return rows;
  }

  template <typename Matrix>
  void SparseDirectCholesky::initialize_from(const Matrix &matrix, const AdditionalData &additional_data)
  {
    cholesky_solver = cholesky::SparseCholesky(solver_settings(additional_data));
    dealii_map      = sparse::DealiiCscMap();
#ifdef DEAL_II_WITH_TRILINOS
    trilinos_positions.clear();
#endif
    factor_and_translate_errors([&]() {
      matrix_csc = sparse::to_csc(matrix);
      copy_values(matrix);
      cholesky_solver.analyze(matrix_csc);
      cholesky_solver.factorize(matrix_csc);
    });
  }

  template <typename Matrix>
  void SparseDirectCholesky::factorize_from(const Matrix &matrix)
  {
    assert_initialized();
    factor_and_translate_errors([&]() {
      copy_values(matrix);
      cholesky_solver.factorize(matrix_csc);
    });
  }

  template <typename Matrix>
  void SparseDirectCholesky::refactorize_from(const Matrix &matrix, const std::vector<size_type> &changed_rows)
  {
    // After a failed factorization, refactorize() of the solver factors in full.
    assert_initialized();
    const std::vector<Index> rows = checked_rows(changed_rows);
    factor_and_translate_errors([&]() {
      copy_values(matrix);
      cholesky_solver.refactorize(matrix_csc, rows);
    });
  }

  void SparseDirectCholesky::copy_values(const dealii::SparseMatrix<double> &matrix)
  {
    // The map is made at the first matrix (kept only if the copy succeeds).
    if (dealii_map.position.empty())
      {
        sparse::DealiiCscMap map = sparse::csc_map(matrix, matrix_csc);
        sparse::copy_values(matrix, map, matrix_csc);
        dealii_map = std::move(map);
      }
    else
      sparse::copy_values(matrix, dealii_map, matrix_csc);
  }

  void SparseDirectCholesky::initialize(const dealii::SparseMatrix<double> &matrix,
                                        const AdditionalData               &additional_data)
  {
    initialize_from(matrix, additional_data);
  }

  void SparseDirectCholesky::factorize(const dealii::SparseMatrix<double> &matrix)
  {
    factorize_from(matrix);
  }

  void SparseDirectCholesky::refactorize(const dealii::SparseMatrix<double> &matrix,
                                         const std::vector<size_type>       &changed_rows)
  {
    refactorize_from(matrix, changed_rows);
  }

  namespace
  {
    /** The columns of @p c in the solver's form (n x k, CSC), without the stored entries that are zero. */
    sparse::CSCMatrix modification_columns(const dealii::SparseMatrix<double> &c)
    {
      const sparse::CSCMatrix stored  = sparse::to_csc(c);
      sparse::CSCMatrix       columns = sparse::CSCMatrix::zero(stored.n_rows, stored.n_cols);
      for (Index t = 0; t < stored.n_cols; ++t)
        {
          for (Index k = stored.column_start[t]; k < stored.column_start[t + 1]; ++k)
            if (stored.values[k] != 0.)
              {
                columns.row_index.push_back(stored.row_index[k]);
                columns.values.push_back(stored.values[k]);
              }
          columns.column_start[t + 1] = static_cast<Index>(columns.row_index.size());
        }
      return columns;
    }
  } // namespace

  void SparseDirectCholesky::modify(const dealii::SparseMatrix<double> &C, const double sign)
  {
    assert_factored();
    // The solver's errors leave its factor as it was: unlike a failed factorization's,
    // they become exceptions of their own.
    try
      {
        const sparse::CSCMatrix columns = modification_columns(C);
        if (sign > 0)
          cholesky_solver.update(columns);
        else
          cholesky_solver.downdate(columns);
      }
    catch (const NotPositiveDefinite &error)
      {
        AssertThrow(false, ExcDowndateNotPositiveDefinite(error.column, error.pivot));
      }
    catch (const Error &error)
      {
        AssertThrow(false, ExcInvalidModification(error.what()));
      }
  }

  void SparseDirectCholesky::update(const dealii::SparseMatrix<double> &C)
  {
    modify(C, 1.);
  }

  void SparseDirectCholesky::downdate(const dealii::SparseMatrix<double> &C)
  {
    modify(C, -1.);
  }

#ifdef DEAL_II_WITH_TRILINOS
  namespace
  {
    /** Throw ExcNotOneProcess unless @p communicator has a single process. */
    void assert_one_process(const MPI_Comm communicator)
    {
      const unsigned int n_processes = dealii::Utilities::MPI::n_mpi_processes(communicator);
      AssertThrow(n_processes == 1, SparseDirectCholesky::ExcNotOneProcess(n_processes));
    }
  } // namespace

  void SparseDirectCholesky::copy_values(const dealii::TrilinosWrappers::SparseMatrix &matrix)
  {
    if (trilinos_positions.empty())
      {
        std::vector<Index> positions = sparse::csc_positions(matrix, matrix_csc);
        sparse::copy_values(matrix, positions, matrix_csc);
        trilinos_positions = std::move(positions);
      }
    else
      sparse::copy_values(matrix, trilinos_positions, matrix_csc);
  }

  void SparseDirectCholesky::initialize(const dealii::TrilinosWrappers::SparseMatrix &matrix,
                                        const AdditionalData                         &additional_data)
  {
    assert_one_process(matrix.get_mpi_communicator());
    initialize_from(matrix, additional_data);
  }

  void SparseDirectCholesky::factorize(const dealii::TrilinosWrappers::SparseMatrix &matrix)
  {
    assert_one_process(matrix.get_mpi_communicator());
    factorize_from(matrix);
  }

  void SparseDirectCholesky::refactorize(const dealii::TrilinosWrappers::SparseMatrix &matrix,
                                         const std::vector<size_type>                 &changed_rows)
  {
    assert_one_process(matrix.get_mpi_communicator());
    refactorize_from(matrix, changed_rows);
  }
#endif

  void SparseDirectCholesky::solve(const double *b, double *x) const
  {
    cholesky_solver.solve(b, x, 1);
  }

  void SparseDirectCholesky::vmult(dealii::Vector<double> &dst, const dealii::Vector<double> &src) const
  {
    assert_factored();
    AssertThrow(src.size() == n(), dealii::ExcDimensionMismatch(src.size(), n()));
    AssertThrow(dst.size() == m(), dealii::ExcDimensionMismatch(dst.size(), m()));
    solve(src.begin(), dst.begin());
  }

  void SparseDirectCholesky::Tvmult(dealii::Vector<double> &dst, const dealii::Vector<double> &src) const
  {
    vmult(dst, src);
  }

  void SparseDirectCholesky::solve(dealii::Vector<double> &rhs_and_solution) const
  {
    vmult(rhs_and_solution, rhs_and_solution);
  }

#ifdef DEAL_II_WITH_TRILINOS
  void SparseDirectCholesky::vmult(dealii::TrilinosWrappers::MPI::Vector       &dst,
                                   const dealii::TrilinosWrappers::MPI::Vector &src) const
  {
    assert_factored();
    assert_one_process(src.get_mpi_communicator());
    assert_one_process(dst.get_mpi_communicator());
    AssertThrow(src.size() == n(), dealii::ExcDimensionMismatch(src.size(), n()));
    AssertThrow(dst.size() == m(), dealii::ExcDimensionMismatch(dst.size(), m()));
    // One process: the local elements are the whole vector, in order.
    solve(src.begin(), dst.begin());
  }

  void SparseDirectCholesky::Tvmult(dealii::TrilinosWrappers::MPI::Vector       &dst,
                                    const dealii::TrilinosWrappers::MPI::Vector &src) const
  {
    vmult(dst, src);
  }

  void SparseDirectCholesky::solve(dealii::TrilinosWrappers::MPI::Vector &rhs_and_solution) const
  {
    vmult(rhs_and_solution, rhs_and_solution);
  }
#endif

  SparseDirectCholesky::size_type SparseDirectCholesky::m() const
  {
    return cholesky_solver.statistics().n;
  }

  SparseDirectCholesky::size_type SparseDirectCholesky::n() const
  {
    return cholesky_solver.statistics().n;
  }

  const cholesky::SparseCholesky::Statistics &SparseDirectCholesky::statistics() const
  {
    return cholesky_solver.statistics();
  }
} // namespace warpchol
