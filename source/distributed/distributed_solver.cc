#include <warpchol/backends/trilinos_amg_cg.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/distributed/distributed_solver.h>

#include <deal.II/lac/petsc_solver.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>
#include <deal.II/lac/trilinos_vector.h>


namespace warpchol::distributed
{
  unsigned int DistributedLinearSolver::last_iterations() const
  {
    return 0;
  }

  double DistributedLinearSolver::last_setup_seconds() const
  {
    return setup_seconds;
  }

  namespace
  {
    using dealii::types::global_dof_index;

    /**
     * What both solvers share: a distributed matrix of @p Matrix (Trilinos' or PETSc's,
     * whose add() and compress() read alike) on the body's pattern, and whether its values
     * changed since it was last factored.
     */
    template <class Matrix>
    class AssembledSolver : public DistributedLinearSolver
    {
    public:
      void set_zero() override
      {
        matrix  = 0;
        changed = true;
      }

      void add(const std::array<global_dof_index, 12> &dofs, const std::array<bool, 12> &free,
               const fem::ElementMatrix &element_matrix, const double factor) override
      {
        std::array<global_dof_index, 12> columns;
        std::array<double, 12>           values;
        for (unsigned int i = 0; i < 12; ++i)
          {
            if (!free[i])
              continue;
            unsigned int n = 0;
            for (unsigned int j = 0; j < 12; ++j)
              if (free[j])
                {
                  columns[n] = dofs[j];
                  values[n]  = factor * element_matrix(i, j);
                  ++n;
                }
            matrix.add(dofs[i], n, columns.data(), values.data(), false, false);
          }
        changed = true;
      }

      void add_diagonal(const global_dof_index dof, const double value) override
      {
        matrix.add(dof, dof, value);
        changed = true;
      }

      void compress() override
      {
        matrix.compress(dealii::VectorOperation::add);
      }

    protected:
      Matrix matrix;
      bool   changed = true;
    };

    /**
     * The body's pattern as Trilinos' own, row by row: the reinit() of a Trilinos matrix
     * from a deal.II pattern is a member template whose mangled name clang (the sanitizer
     * build) and the gcc that built deal.II write differently, the one from a Trilinos
     * pattern is not a template.
     */
    dealii::TrilinosWrappers::SparsityPattern trilinos_pattern(const DistributedBody &body)
    {
      const dealii::DynamicSparsityPattern     &pattern = body.sparsity_pattern();
      dealii::TrilinosWrappers::SparsityPattern trilinos(body.locally_owned_dofs(), body.locally_owned_dofs(),
                                                         body.communicator());
      std::vector<global_dof_index>             columns;
      for (const global_dof_index row : body.locally_owned_dofs())
        {
          columns.resize(pattern.row_length(row));
          for (unsigned int k = 0; k < columns.size(); ++k)
            columns[k] = pattern.column_number(row, k);
          trilinos.add_entries(row, columns.begin(), columns.end(), true);
        }
      trilinos.compress();
      return trilinos;
    }

    /**
     * CG with ML's smoothed-aggregation AMG (the settings of the serial backend
     * trilinos_amg_cg: Chebyshev smoother of degree 2, the six rigid-body modes as near
     * null space, aggregates of whole vertices), the hierarchy built on the first matrix
     * solved and reused while the values change: the finest level reads the matrix itself.
     */
    class AmgCgSolver : public AssembledSolver<dealii::TrilinosWrappers::SparseMatrix>
    {
    public:
      AmgCgSolver(const app::parameters::Distributed &settings, const DistributedBody &body,
                  const std::vector<double> &rigid_body_modes)
        : settings(settings)
        , null_space(rigid_body_modes)
      {
        matrix.reinit(trilinos_pattern(body));
        rhs.reinit(body.locally_owned_dofs(), body.communicator());
        solution.reinit(body.locally_owned_dofs(), body.communicator());
      }

      std::string name() const override
      {
        return "amg_cg";
      }

      void solve(const std::vector<double> &b, std::vector<double> &x) override
      {
        setup_seconds = 0;
        if (!set_up)
          {
            Stopwatch watch;
            set_up_preconditioner();
            setup_seconds = watch.seconds();
            set_up = true;
          }
        backends::solve_with_amg_cg(matrix, preconditioner, settings.tolerance, settings.max_iterations, b, x, rhs,
                                    solution, iterations);
      }

      unsigned int last_iterations() const override
      {
        return iterations;
      }

    private:
      void set_up_preconditioner()
      {
        backends::initialize_elasticity_amg(preconditioner, matrix, null_space);
      }

      const app::parameters::Distributed        settings;
      /** ML reads its near null space from this bare array while the hierarchy lives. */
      std::vector<double>                       null_space;
      dealii::TrilinosWrappers::PreconditionAMG preconditioner;
      bool                                      set_up = false;
      dealii::TrilinosWrappers::MPI::Vector     rhs;
      dealii::TrilinosWrappers::MPI::Vector     solution;
      unsigned int                              iterations = 0;
    };

    /**
     * MUMPS through deal.II's PETSc wrappers (PETScWrappers::SparseDirectMUMPS, symmetric
     * mode: an LDL^T factorization): factored again, analysis included, at the first solve
     * after the values changed.
     */
    class MumpsSolver : public AssembledSolver<dealii::PETScWrappers::MPI::SparseMatrix>
    {
    public:
      explicit MumpsSolver(const DistributedBody &body)
        : comm(body.communicator())
      {
        matrix.reinit(body.locally_owned_dofs(), body.locally_owned_dofs(), body.sparsity_pattern(), comm);
        rhs.reinit(body.locally_owned_dofs(), comm);
        solution.reinit(body.locally_owned_dofs(), comm);
        for (const auto dof : body.locally_owned_dofs())
          owned.push_back(dof);
      }

      std::string name() const override
      {
        return "mumps";
      }

      void solve(const std::vector<double> &b, std::vector<double> &x) override
      {
        Stopwatch watch;
        const bool refactor = changed || !mumps;
        if (refactor)
          {
            mumps = std::make_unique<dealii::PETScWrappers::SparseDirectMUMPS>(control, comm);
            mumps->set_symmetric_mode(true);
            changed = false;
          }
        rhs.set(owned, b);
        rhs.compress(dealii::VectorOperation::insert);
        mumps->solve(matrix, solution, rhs);
        x.resize(owned.size());
        solution.extract_subvector_to(owned, x);
        // The factorization is inside the first solve of a new matrix: all of it counts
        // as set-up then.
        setup_seconds = refactor ? watch.seconds() : 0;
      }

    private:
      MPI_Comm                                                   comm;
      dealii::SolverControl                                      control;
      std::unique_ptr<dealii::PETScWrappers::SparseDirectMUMPS> mumps;
      dealii::PETScWrappers::MPI::Vector                         rhs;
      dealii::PETScWrappers::MPI::Vector                         solution;
      std::vector<global_dof_index>                              owned;
    };
  } // namespace

  std::unique_ptr<DistributedLinearSolver>
  create_distributed_solver(const app::parameters::Distributed &settings, const DistributedBody &body,
                            const std::vector<double> &rigid_body_modes)
  {
    if (settings.linear_solver == "mumps")
      return std::make_unique<MumpsSolver>(body);
    if (settings.linear_solver == "amg_cg")
      return std::make_unique<AmgCgSolver>(settings, body, rigid_body_modes);
    throw InputError("unknown distributed linear solver " + quote(settings.linear_solver) + " (valid: amg_cg, mumps)");
  }
} // namespace warpchol::distributed
