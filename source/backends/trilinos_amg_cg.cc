#include <warpchol/backends/trilinos_amg_cg.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/sparse/dealii_conversion.h>

#include <deal.II/base/mpi.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <Epetra_CrsMatrix.h>
#include <Epetra_MultiVector.h>
#include <Epetra_Vector.h>
#include <Teuchos_ParameterList.hpp>

#include <algorithm>
#include <iterator>

namespace warpchol::backends
{
  namespace
  {
    constexpr unsigned int n_rigid_body_modes = 6;

    /**
     * CG's product with A, y = A x, as TrilinosWrappers::SparseMatrix::vmult() computes
     * it (one Epetra Multiply), but not a template: clang (the sanitizer build) mangles
     * that member template's enable_if return type otherwise than the gcc that built
     * deal.II, so a call to it does not link there.
     */
    class EpetraProduct
    {
    public:
      explicit EpetraProduct(const Epetra_CrsMatrix &matrix)
        : matrix(matrix)
      {}

      /** Serial vectors, through Epetra views of their storage. */
      void vmult(dealii::Vector<double> &y, const dealii::Vector<double> &x) const
      {
        // Epetra's views take non-const pointers; x is only read. The graph's maps, as
        // in set_up_matrix().
        const Epetra_Vector x_view(View, matrix.Graph().DomainMap(), const_cast<double *>(x.begin()));
        Epetra_Vector       y_view(View, matrix.Graph().RangeMap(), y.begin());
        multiply(x_view, y_view);
      }

      /** Distributed vectors: their own Epetra vectors. */
      void vmult(dealii::TrilinosWrappers::MPI::Vector &y, const dealii::TrilinosWrappers::MPI::Vector &x) const
      {
        multiply(x.trilinos_vector(), y.trilinos_vector());
      }

    private:
      void multiply(const Epetra_MultiVector &x, Epetra_MultiVector &y) const
      {
        if (matrix.Multiply(false, x, y) != 0)
          throw MatrixError("Trilinos AMG-CG: Epetra's matrix-vector product failed");
      }

      const Epetra_CrsMatrix &matrix;
    };

    template <class VectorType>
    void solve_with_cg(const dealii::TrilinosWrappers::SparseMatrix    &matrix,
                       const dealii::TrilinosWrappers::PreconditionAMG &preconditioner, const double tolerance,
                       const unsigned int max_iterations, const std::vector<double> &b, std::vector<double> &x,
                       VectorType &rhs, VectorType &solution, unsigned int &iterations)
    {
      iterations = 0;
      std::copy(b.begin(), b.end(), rhs.begin());
      const double b_norm = rhs.l2_norm();
      // x = 0 solves A x = 0 exactly; from a guess, no residual would reach 0 |b|.
      if (b_norm == 0)
        {
          x.assign(b.size(), 0.);
          return;
        }
      if (x.size() == b.size())
        std::copy(x.begin(), x.end(), solution.begin());
      else
        solution = 0;

      // |b - A x| <= tolerance |b| (SolverControl compares the unscaled residual norm).
      dealii::SolverControl    control(max_iterations, tolerance * b_norm, false, false);
      dealii::SolverCG<VectorType> cg(control);
      try
        {
          cg.solve(EpetraProduct(matrix.trilinos_matrix()), solution, rhs, preconditioner);
        }
      catch (const dealii::SolverControl::NoConvergence &)
        {
          iterations = control.last_step();
          throw MatrixError("Trilinos AMG-CG did not reach the tolerance " + format_number(tolerance) + " in " +
                            std::to_string(control.last_step()) + " iterations");
        }
      iterations = control.last_step();
      x.assign(solution.begin(), solution.end());
    }
  } // namespace

  void initialize_elasticity_amg(dealii::TrilinosWrappers::PreconditionAMG    &preconditioner,
                                 const dealii::TrilinosWrappers::SparseMatrix &matrix,
                                 std::vector<double>                          &null_space)
  {
    if (null_space.size() != n_rigid_body_modes * static_cast<std::size_t>(matrix.local_size()))
      throw MatrixError("Trilinos AMG-CG: " + std::to_string(null_space.size()) + " null space entries for " +
                        std::to_string(matrix.local_size()) + " rows and 6 rigid-body modes");
    // deal.II's elliptic defaults: smoothed aggregation, a Chebyshev smoother of degree 2,
    // KLU on the coarsest level. Chebyshev rather than symmetric Gauss-Seidel: on the torus
    // SGS saves a few iterations (5 instead of 8 to 1e-6) but costs more per iteration, and
    // with the hierarchy of the rest matrix it stalls once the elements are rotated by a
    // radian or more, where Chebyshev still converges.
    dealii::TrilinosWrappers::PreconditionAMG::AdditionalData data;
    data.elliptic              = true;
    data.higher_order_elements = false;
    data.smoother_sweeps       = 2;
    data.aggregation_threshold = 1e-4;
    data.smoother_type         = "Chebyshev";

    Teuchos::ParameterList              parameters;
    std::unique_ptr<Epetra_MultiVector> unused_constant_modes;
    data.set_parameters(parameters, unused_constant_modes, matrix);
    // AdditionalData::constant_modes takes only the translations (as bools), so the six
    // modes go straight to ML (the rank's rows, mode after mode). Aggregates are made of
    // whole vertices (3 consecutive rows), on which the rotations are representable.
    parameters.set("PDE equations", 3);
    parameters.set("null space: type", "pre-computed");
    parameters.set("null space: dimension", static_cast<int>(n_rigid_body_modes));
    parameters.set("null space: vectors", null_space.data());
    preconditioner.initialize(matrix, parameters);
  }

  void solve_with_amg_cg(const dealii::TrilinosWrappers::SparseMatrix    &matrix,
                         const dealii::TrilinosWrappers::PreconditionAMG &preconditioner, const double tolerance,
                         const unsigned int max_iterations, const std::vector<double> &b, std::vector<double> &x,
                         dealii::Vector<double> &rhs, dealii::Vector<double> &solution, unsigned int &iterations)
  {
    solve_with_cg(matrix, preconditioner, tolerance, max_iterations, b, x, rhs, solution, iterations);
  }

  void solve_with_amg_cg(const dealii::TrilinosWrappers::SparseMatrix    &matrix,
                         const dealii::TrilinosWrappers::PreconditionAMG &preconditioner, const double tolerance,
                         const unsigned int max_iterations, const std::vector<double> &b, std::vector<double> &x,
                         dealii::TrilinosWrappers::MPI::Vector &rhs, dealii::TrilinosWrappers::MPI::Vector &solution,
                         unsigned int &iterations)
  {
    solve_with_cg(matrix, preconditioner, tolerance, max_iterations, b, x, rhs, solution, iterations);
  }

  struct TrilinosAmgCgSolver::Implementation
  {
    Settings settings;
    Index    n = 0;
    /**
     * The rigid-body modes, mode after mode (n x 6, column-major): the array ML reads its
     * near null space from ("null space: vectors" is a bare pointer).
     */
    std::vector<double> null_space;

    /** A's copy, which the finest level of the hierarchy and CG's products read. */
    dealii::TrilinosWrappers::SparseMatrix matrix;
    /** Declared after the matrix, so destroyed before it: ML holds a pointer to it. */
    dealii::TrilinosWrappers::PreconditionAMG preconditioner;
    bool                                      set_up = false;

    /**
     * Per entry of the Trilinos matrix, row after row in its storage order, the position
     * of the same entry in the CSC values (full storage: column r of the CSC is row r of
     * the symmetric A), so that a change of values is one gather.
     */
    std::vector<Index> csc_position;

    dealii::Vector<double> rhs;
    dealii::Vector<double> solution;
    unsigned int           last_iterations = 0;
    std::size_t            memory_bytes    = 0;

    void set_up_matrix(const dealii::SparseMatrix<double> &dealii_matrix, const sparse::CSCMatrix &csc);
    void copy_values(const sparse::CSCMatrix &csc);
    void set_up_preconditioner();
  };

  void TrilinosAmgCgSolver::Implementation::set_up_matrix(const dealii::SparseMatrix<double> &dealii_matrix,
                                                          const sparse::CSCMatrix            &csc)
  {
    // The pattern only (serial: every row on MPI_COMM_SELF); the values come from the CSC,
    // whose pattern is the deal.II matrix' with every entry kept.
    matrix.reinit(dealii_matrix.get_sparsity_pattern());
    if (csc.storage != sparse::Storage::full || csc.n_cols != n ||
        static_cast<dealii::types::global_dof_index>(csc.n_nonzeros()) != matrix.n_nonzero_elements())
      throw MatrixError("Trilinos AMG-CG: the CSC form does not hold the deal.II matrix' entries (full storage, " +
                        std::to_string(matrix.n_nonzero_elements()) + " entries)");

    // Entry (row, column) reads A(column, row), the same value, from the CSC's column row.
    csc_position.clear();
    csc_position.reserve(csc.n_nonzeros());
    sparse::for_each_stored_entry(matrix, [&](const Index row, const Index column, double) {
      const auto begin    = csc.row_index.begin() + csc.column_start[row];
      const auto end      = csc.row_index.begin() + csc.column_start[row + 1];
      const auto position = std::lower_bound(begin, end, column);
      if (position == end || *position != column)
        throw MatrixError("Trilinos AMG-CG: entry (" + std::to_string(row) + ", " + std::to_string(column) +
                          ") is not in the CSC form");
      csc_position.push_back(std::distance(csc.row_index.begin(), position));
    });
  }

  void TrilinosAmgCgSolver::Implementation::copy_values(const sparse::CSCMatrix &csc)
  {
    // Write through Epetra's row views: one gather in the rows' order, no search (deal.II's
    // reinit(const SparseMatrix &) looks every entry up). Epetra caches nothing derived
    // from the values (its norms are computed on each call).
    const Epetra_CrsMatrix &epetra   = matrix.trilinos_matrix();
    std::size_t             position = 0;
    for (int row = 0; row < epetra.NumMyRows(); ++row)
      {
        int     n_entries = 0;
        double *values    = nullptr;
        epetra.ExtractMyRowView(row, n_entries, values);
        for (int k = 0; k < n_entries; ++k)
          values[k] = csc.values[csc_position[position++]];
      }
  }

  void TrilinosAmgCgSolver::Implementation::set_up_preconditioner()
  {
    initialize_elasticity_amg(preconditioner, matrix, null_space);
  }

  TrilinosAmgCgSolver::TrilinosAmgCgSolver(const Settings &settings, const std::vector<std::vector<double>> &rigid_body_modes)
    : implementation(std::make_unique<Implementation>())
  {
    // Without MPI, Epetra's first call would abort the program with MPI's own message.
    if (!dealii::Utilities::MPI::job_supports_mpi())
      throw Error("Trilinos AMG-CG needs MPI: create a dealii::Utilities::MPI::MPI_InitFinalize in main()");
    if (rigid_body_modes.size() != n_rigid_body_modes)
      throw MatrixError("Trilinos AMG-CG: expected 6 rigid-body modes, got " + std::to_string(rigid_body_modes.size()));
    implementation->settings = settings;
    implementation->n        = static_cast<Index>(rigid_body_modes[0].size());
    for (const std::vector<double> &mode : rigid_body_modes)
      {
        if (static_cast<Index>(mode.size()) != implementation->n)
          throw MatrixError("Trilinos AMG-CG: rigid-body modes of different sizes (" + std::to_string(mode.size()) +
                            " and " + std::to_string(implementation->n) + ")");
        implementation->null_space.insert(implementation->null_space.end(), mode.begin(), mode.end());
      }
  }

  TrilinosAmgCgSolver::~TrilinosAmgCgSolver() = default;

  std::string TrilinosAmgCgSolver::name() const
  {
    return "trilinos_amg_cg";
  }

  void TrilinosAmgCgSolver::factorize(const dealii::SparseMatrix<double> &matrix, const sparse::CSCMatrix &csc)
  {
    Implementation &self = *implementation;
    if (static_cast<Index>(matrix.m()) != self.n || static_cast<Index>(matrix.n()) != self.n || csc.n_cols != self.n)
      throw MatrixError("Trilinos AMG-CG: a matrix of " + std::to_string(matrix.m()) + " x " +
                        std::to_string(matrix.n()) + " for rigid-body modes of " + std::to_string(self.n) + " entries");
    // A system with no unknowns (every vertex fixed) has nothing to set up or solve.
    if (self.n == 0)
      return;
    if (self.set_up)
      {
        if (static_cast<std::size_t>(csc.n_nonzeros()) != self.csc_position.size())
          throw MatrixError("Trilinos AMG-CG: a matrix of " + std::to_string(csc.n_nonzeros()) +
                            " entries after one of " + std::to_string(self.csc_position.size()) +
                            " (the pattern must not change)");
        self.copy_values(csc);
        return;
      }

    self.memory_bytes = heap_growth_of([&] {
      self.set_up_matrix(matrix, csc);
      self.copy_values(csc);
      self.set_up_preconditioner();
      self.rhs.reinit(self.n);
      self.solution.reinit(self.n);
    });
    self.set_up = true;
  }

  void TrilinosAmgCgSolver::solve(const std::vector<double> &b, std::vector<double> &x)
  {
    Implementation &self = *implementation;
    if (static_cast<Index>(b.size()) != self.n)
      throw MatrixError("Trilinos AMG-CG: a right-hand side of " + std::to_string(b.size()) + " entries for " +
                        std::to_string(self.n) + " unknowns");
    self.last_iterations = 0;
    if (self.n == 0)
      {
        x.clear();
        return;
      }
    if (!self.set_up)
      throw MatrixError("Trilinos AMG-CG: solve() before factorize()");

    solve_with_amg_cg(self.matrix, self.preconditioner, self.settings.tolerance, self.settings.max_iterations, b, x,
                      self.rhs, self.solution, self.last_iterations);
  }

  bool TrilinosAmgCgSolver::is_iterative() const
  {
    return true;
  }

  unsigned int TrilinosAmgCgSolver::last_iterations() const
  {
    return implementation->last_iterations;
  }

  std::size_t TrilinosAmgCgSolver::memory_bytes() const
  {
    return implementation->memory_bytes;
  }
} // namespace warpchol::backends
