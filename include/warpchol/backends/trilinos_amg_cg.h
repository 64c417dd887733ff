#pragma once

#include <warpchol/backends/linear_solver.h>

#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/lac/vector.h>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

/**
 * @file
 * The Trilinos AMG-CG backend: what a deal.II user would write for a slowly changing
 * elasticity matrix (step-8 with TrilinosWrappers, step-31's PreconditionAMG).
 */
namespace warpchol::backends
{
  /**
   * Set @p preconditioner up as ML's smoothed-aggregation AMG for elasticity on @p matrix
   * (serial or distributed): deal.II's elliptic defaults with a Chebyshev smoother of
   * degree 2, and @p null_space, the six rigid-body modes over the rank's rows (mode after
   * mode), as near null space; ML reads that array while the hierarchy lives. The rows of
   * a vertex must be consecutive. What both Trilinos AMG-CG solvers (this backend, and
   * distributed runs) build.
   */
  void initialize_elasticity_amg(dealii::TrilinosWrappers::PreconditionAMG    &preconditioner,
                                 const dealii::TrilinosWrappers::SparseMatrix &matrix,
                                 std::vector<double>                          &null_space);

  /**
   * x = A^-1 b by deal.II's SolverCG on @p matrix, preconditioned by @p preconditioner,
   * until |b - A x| <= @p tolerance |b|, from @p x (from zero if its size is not b's);
   * x = 0 when b = 0. @p rhs and @p solution are work vectors over the matrix' rows (the
   * rank's rows when distributed, where the norms are global). @p iterations is set to
   * CG's iterations, also when it throws MatrixError "Trilinos AMG-CG did not reach the
   * tolerance T in N iterations" after @p max_iterations. What both Trilinos AMG-CG
   * solvers (this backend, and distributed runs) solve with.
   */
  void solve_with_amg_cg(const dealii::TrilinosWrappers::SparseMatrix    &matrix,
                         const dealii::TrilinosWrappers::PreconditionAMG &preconditioner, double tolerance,
                         unsigned int max_iterations, const std::vector<double> &b, std::vector<double> &x,
                         dealii::Vector<double> &rhs, dealii::Vector<double> &solution, unsigned int &iterations);
  /** The same on distributed vectors. */
  void solve_with_amg_cg(const dealii::TrilinosWrappers::SparseMatrix    &matrix,
                         const dealii::TrilinosWrappers::PreconditionAMG &preconditioner, double tolerance,
                         unsigned int max_iterations, const std::vector<double> &b, std::vector<double> &x,
                         dealii::TrilinosWrappers::MPI::Vector &rhs, dealii::TrilinosWrappers::MPI::Vector &solution,
                         unsigned int &iterations);

  /**
   * Conjugate gradients (deal.II's SolverCG) on a Trilinos copy of A, preconditioned by
   * ML's smoothed-aggregation algebraic multigrid (TrilinosWrappers::PreconditionAMG) with
   * the six rigid-body modes as near null space.
   *
   * The preconditioner is set up once, at the first factorize(), and kept while the
   * matrix changes: later calls copy the new values into the Trilinos matrix only. The
   * finest level of the hierarchy reads that matrix, so CG's products and the smoother
   * see the new values; the aggregates, the coarse matrices, the smoother's inverse
   * diagonal and its bound of the spectrum stay those of the first matrix. That is what
   * a deal.II user does with a slowly changing matrix, and it holds while the changes stay
   * small: on the report's torus (E = 50 Pa, dt = 0.01 s, 60k unknowns) the hierarchy of
   * the rest matrix takes 15 iterations to 1e-6 on the rest matrix and with the elements
   * rotated by up to 0.4 rad (a twist about the x axis), 38 at 0.8 rad, 157 at 1.2 rad,
   * while a hierarchy of the twisted matrix itself takes 15. A matrix stiffer than the
   * first outgrows the smoother's bound of the spectrum: with the stiffness part 1.25x as
   * large CG takes 49 iterations, at 1.5x 486, at 2x it does not converge. Create a new
   * solver when the time step, the material or the tool's springs change.
   *
   * Trilinos needs MPI: the program must hold a dealii::Utilities::MPI::MPI_InitFinalize
   * while a solver exists. It runs serially, on MPI_COMM_SELF.
   */
  class TrilinosAmgCgSolver : public LinearSolver
  {
  public:
    /**
     * A solver that stops as @p settings say (tolerance, max_iterations), for matrices
     * whose near null space is @p rigid_body_modes: 6 vectors of n entries (3 translations,
     * 3 rotations about the rest centre) in the unknowns' numbering 3 k + c. Throws
     * MatrixError if they are not 6 vectors of one size, or Error if MPI is not
     * initialized.
     */
    TrilinosAmgCgSolver(const Settings &settings, const std::vector<std::vector<double>> &rigid_body_modes);
    ~TrilinosAmgCgSolver() override;
    TrilinosAmgCgSolver(const TrilinosAmgCgSolver &) = delete;
    TrilinosAmgCgSolver &operator=(const TrilinosAmgCgSolver &) = delete;

    /** "trilinos_amg_cg". */
    std::string name() const override;

    /**
     * The first call copies @p matrix into Trilinos and sets the AMG hierarchy up; later
     * calls copy its values only (its pattern must stay that of the first call). Throws
     * MatrixError if its size differs from the rigid-body modes'.
     */
    void factorize(const dealii::SparseMatrix<double> &matrix, const sparse::CSCMatrix &csc) override;

    /**
     * CG from @p x (from zero if its size is not n) until |b - A x| <= tolerance |b|.
     * Throws MatrixError "Trilinos AMG-CG did not reach the tolerance T in N iterations".
     */
    void solve(const std::vector<double> &b, std::vector<double> &x) override;

    /** True: CG from the guess it is given. */
    bool is_iterative() const override;

    unsigned int last_iterations() const override;

    /** Heap bytes allocated by the first factorize(): the matrix copy and the hierarchy. */
    std::size_t memory_bytes() const override;

  private:
    struct Implementation;
    std::unique_ptr<Implementation> implementation;
  };
} // namespace warpchol::backends
