#pragma once

#include <warpchol/app/parameters.h>
#include <warpchol/distributed/distributed_body.h>
#include <warpchol/fem/small_dense.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

/**
 * @file
 * The distributed linear solvers of a step: the global matrix, assembled from the ranks'
 * element matrices, and its solve, on the engines made for it (Trilinos, PETSc/MUMPS).
 */
namespace warpchol::distributed
{
  /**
   * The step's matrix over every dof of a DistributedBody (rows of fixed vertices: 1 on
   * the diagonal) and its solve. Vectors are the rank's owned rows, in the order of
   * locally_owned_dofs().
   */
  class DistributedLinearSolver
  {
  public:
    virtual ~DistributedLinearSolver() = default;

    /** "amg_cg" or "mumps", as Distributed/Linear solver writes it. */
    virtual std::string name() const = 0;

    /** Set every entry to 0 (the pattern stays). */
    virtual void set_zero() = 0;
    /**
     * Add @p factor times the 12x12 element matrix @p matrix (rows 3 a + c) at @p dofs,
     * leaving out the rows and columns whose @p free entry is false (fixed vertices).
     */
    virtual void add(const std::array<dealii::types::global_dof_index, 12> &dofs,
                     const std::array<bool, 12> &free, const fem::ElementMatrix &matrix,
                     double factor) = 0;
    /** Add @p value to the diagonal entry of @p dof. */
    virtual void add_diagonal(dealii::types::global_dof_index dof, double value) = 0;
    /** Exchange what the ranks added to each other's rows; the matrix is then ready. */
    virtual void compress() = 0;

    /**
     * x = A^-1 b. An iterative solver starts from @p x (its last step's solution, a good
     * guess) and throws MatrixError if it does not reach its tolerance.
     */
    virtual void solve(const std::vector<double> &b, std::vector<double> &x) = 0;
    /** Iterations of the last solve (0 for a direct solver). */
    virtual unsigned int last_iterations() const;
    /** Seconds of the last solve spent setting up: the AMG hierarchy or a factorization. */
    double last_setup_seconds() const;

  protected:
    double setup_seconds = 0;
  };

  /**
   * The solver Distributed/Linear solver names, for the matrix of @p body. @p rigid_body_modes:
   * the six modes over the owned rows (n_owned x 6, mode after mode), 0 on fixed dofs, the
   * near null space ML's aggregation needs for elasticity.
   */
  std::unique_ptr<DistributedLinearSolver>
  create_distributed_solver(const app::parameters::Distributed &settings, const DistributedBody &body,
                            const std::vector<double> &rigid_body_modes);
} // namespace warpchol::distributed
