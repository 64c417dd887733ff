/* step-8-partial: deal.II's step-8 (linear elasticity), with a material that changes in
 * a small region from one step to the next, solved by warpchol::SparseDirectCholesky.
 *
 * A beam, clamped at one end, bends under its own weight. At every step a crack-like
 * damage grows at a new place along its top: the cells within a small ball lose part of
 * their stiffness. Only the rows of those cells' degrees of freedom change in the system
 * matrix, and SparseDirectCholesky::refactorize() recomputes only the columns of the
 * Cholesky factor that depend on them, instead of factoring the whole matrix again.
 *
 * For each step the program prints what that partial refactorization cost against a full
 * factorization of the same matrix (flops and time), and the largest difference between
 * its solution and the one of a fresh factorization, which it computes as well: they agree
 * to rounding, since the columns that are kept do not depend on what changed, and the
 * others are computed again from the new matrix.
 *
 *   step-8-partial [cells across the beam (8)] [steps (5)]
 */

#include <deal.II/base/function.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/timer.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <deal.II/numerics/vector_tools.h>

// The solver: the interface of deal.II's SparseDirectUMFPACK, plus refactorize().
#include <warpchol/lac/sparse_direct_cholesky.h>

#include <algorithm>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <limits>
#include <vector>

namespace Step8Partial
{
  using namespace dealii;

  template <int dim>
  class ElasticProblem
  {
  public:
    /** A beam of 4n x n x n cells (n = @p cells_across), damaged in @p n_steps steps. */
    ElasticProblem(unsigned int cells_across, unsigned int n_steps);
    void run();

  private:
    void setup_system();
    void damage_material(unsigned int step);
    void assemble_system();
    void solve(unsigned int step);

    const unsigned int cells_across;
    const unsigned int n_steps;

    Triangulation<dim> triangulation;
    DoFHandler<dim>    dof_handler;
    FESystem<dim>      fe;

    AffineConstraints<double> constraints;
    SparsityPattern           sparsity_pattern;
    SparseMatrix<double>      system_matrix;
    Vector<double>            solution;
    Vector<double>            system_rhs;

    // The stiffness of each cell relative to the intact material (1), and the rows of
    // the degrees of freedom of the cells whose stiffness the last step changed.
    Vector<double>                       cell_stiffness;
    std::vector<types::global_dof_index> changed_rows;
    unsigned int                         n_changed_cells = 0;

    warpchol::SparseDirectCholesky solver;

    // What the partial refactorizations of all steps cost, and how far their solutions
    // were from those of fresh factorizations.
    double partial_flops = 0, full_flops = 0, partial_seconds = 0, full_seconds = 0;
    double largest_difference = 0;
  };


  template <int dim>
  ElasticProblem<dim>::ElasticProblem(const unsigned int cells_across, const unsigned int n_steps)
    : cells_across(cells_across)
    , n_steps(n_steps)
    , dof_handler(triangulation)
    , fe(FE_Q<dim>(1), dim)
  {}


  // The beam [0,4] x [0,1]^(dim-1), clamped at x = 0 (boundary id 0 once colorized).
  template <int dim>
  void ElasticProblem<dim>::setup_system()
  {
    std::vector<unsigned int> repetitions(dim, cells_across);
    repetitions[0] = 4 * cells_across;
    Point<dim> far_corner;
    for (unsigned int d = 0; d < dim; ++d)
      far_corner[d] = (d == 0 ? 4. : 1.);
    GridGenerator::subdivided_hyper_rectangle(triangulation, repetitions, Point<dim>(), far_corner, true);

    dof_handler.distribute_dofs(fe);
    solution.reinit(dof_handler.n_dofs());
    system_rhs.reinit(dof_handler.n_dofs());
    cell_stiffness.reinit(triangulation.n_active_cells());
    cell_stiffness = 1.;

    constraints.clear();
    VectorTools::interpolate_boundary_values(dof_handler, 0, Functions::ZeroFunction<dim>(dim), constraints);
    constraints.close();

    // The pattern is built once: the matrices of all steps share it, and the solver's
    // analysis (ordering, elimination tree, supernodes) with it.
    DynamicSparsityPattern dsp(dof_handler.n_dofs(), dof_handler.n_dofs());
    DoFTools::make_sparsity_pattern(dof_handler, dsp, constraints, false);
    sparsity_pattern.copy_from(dsp);
    system_matrix.reinit(sparsity_pattern);

    std::cout << "Beam of " << triangulation.n_active_cells() << " cells, " << dof_handler.n_dofs()
              << " degrees of freedom" << std::endl;
  }


  // Step k damages the cells within a ball on the top of the beam, at a place that moves
  // from near the free end towards the clamped one: their stiffness falls to a fifth.
  // The rows of their degrees of freedom are the rows that change in the matrix.
  template <int dim>
  void ElasticProblem<dim>::damage_material(const unsigned int step)
  {
    Point<dim> center;
    center[0]       = 3.6 - 3.2 * (step - 1) / std::max(1u, n_steps - 1);
    center[dim - 1] = 1.;
    for (unsigned int d = 1; d < dim - 1; ++d)
      center[d] = 0.5;
    const double radius = 0.3;

    changed_rows.clear();
    n_changed_cells = 0;
    std::vector<types::global_dof_index> local_dof_indices(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->center().distance(center) < radius)
        {
          cell_stiffness[cell->active_cell_index()] *= 0.2;
          ++n_changed_cells;
          cell->get_dof_indices(local_dof_indices);
          changed_rows.insert(changed_rows.end(), local_dof_indices.begin(), local_dof_indices.end());
        }
    // The solver takes the rows in any order and more than once; sorted, they can be
    // counted.
    std::sort(changed_rows.begin(), changed_rows.end());
    changed_rows.erase(std::unique(changed_rows.begin(), changed_rows.end()), changed_rows.end());
  }


  // As in step-8 (with lambda = mu = the cell's stiffness), the whole matrix again:
  // assembling is cheap next to factoring, and the entries of cells that did not change
  // come out as they were. Had the list of changed rows missed one, the solver would
  // find it while copying the values: the list says where to look, it is not trusted.
  template <int dim>
  void ElasticProblem<dim>::assemble_system()
  {
    system_matrix = 0;
    system_rhs    = 0;
    const QGauss<dim>  quadrature_formula(fe.degree + 1);
    FEValues<dim>      fe_values(fe, quadrature_formula,
                            update_values | update_gradients | update_quadrature_points | update_JxW_values);
    const unsigned int dofs_per_cell = fe.n_dofs_per_cell();
    FullMatrix<double> cell_matrix(dofs_per_cell, dofs_per_cell);
    Vector<double>     cell_rhs(dofs_per_cell);
    std::vector<types::global_dof_index> local_dof_indices(dofs_per_cell);

    // The beam's weight.
    Tensor<1, dim> gravity;
    gravity[dim - 1] = -1e-3;

    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        cell_matrix = 0;
        cell_rhs    = 0;
        fe_values.reinit(cell);
        const double lambda = cell_stiffness[cell->active_cell_index()];
        const double mu     = lambda;
        for (const unsigned int i : fe_values.dof_indices())
          {
            const unsigned int component_i = fe.system_to_component_index(i).first;
            for (const unsigned int j : fe_values.dof_indices())
              {
                const unsigned int component_j = fe.system_to_component_index(j).first;
                for (const unsigned int q : fe_values.quadrature_point_indices())
                  cell_matrix(i, j) += ((fe_values.shape_grad(i, q)[component_i] *
                                         fe_values.shape_grad(j, q)[component_j] * lambda) +
                                        (fe_values.shape_grad(i, q)[component_j] *
                                         fe_values.shape_grad(j, q)[component_i] * mu) +
                                        ((component_i == component_j) ?
                                           (fe_values.shape_grad(i, q) * fe_values.shape_grad(j, q) * mu) :
                                           0)) *
                                       fe_values.JxW(q);
              }
            for (const unsigned int q : fe_values.quadrature_point_indices())
              cell_rhs(i) += fe_values.shape_value(i, q) * gravity[component_i] * fe_values.JxW(q);
          }
        cell->get_dof_indices(local_dof_indices);
        constraints.distribute_local_to_global(cell_matrix, cell_rhs, local_dof_indices, system_matrix, system_rhs);
      }
  }


  // The best of three runs of @p work, each on a copy of @p solver as it is now, in CPU
  // seconds: the solver runs on one thread here, and CPU time leaves out what other
  // programs on a shared machine take from it.
  template <typename Work>
  double best_of_three(const warpchol::SparseDirectCholesky &solver, const Work &work)
  {
    double best = std::numeric_limits<double>::max();
    for (unsigned int run = 0; run < 3; ++run)
      {
        warpchol::SparseDirectCholesky copy(solver);
        Timer                          timer;
        work(copy);
        best = std::min(best, timer.cpu_time());
      }
    return best;
  }


  // Step 0 factors the matrix (initialize()); every later step refactorizes only what
  // depends on the changed rows. To show what that saves and that nothing is lost, each
  // step also times the partial refactorization against a full factorization of the
  // same matrix, and compares the solution with that of a fresh factorization.
  template <int dim>
  void ElasticProblem<dim>::solve(const unsigned int step)
  {
    Timer timer;
    if (step == 0)
      {
        solver.initialize(system_matrix);
        timer.stop();
        const auto &statistics = solver.statistics();
        std::cout << "Step 0: factorization of the intact beam: " << std::setprecision(3)
                  << statistics.flops << " flops, fill " << statistics.fill() << ", "
                  << 1e3 * timer.wall_time() << " ms (with the analysis)" << std::endl;
        solver.vmult(solution, system_rhs);
        constraints.distribute(solution);
        return;
      }

    // The partial refactorization, timed on copies of the solver (which holds the factor
    // of the last step), then done on the solver itself.
    const double seconds = best_of_three(solver, [&](warpchol::SparseDirectCholesky &copy) {
      copy.refactorize(system_matrix, changed_rows);
    });
    solver.refactorize(system_matrix, changed_rows);
    solver.vmult(solution, system_rhs);
    constraints.distribute(solution);

    // A fresh factorization, and the time of a full one (without the analysis).
    warpchol::SparseDirectCholesky fresh;
    fresh.initialize(system_matrix);
    const double fresh_seconds = best_of_three(fresh, [&](warpchol::SparseDirectCholesky &copy) {
      copy.factorize(system_matrix);
    });
    Vector<double> fresh_solution(solution.size());
    fresh.vmult(fresh_solution, system_rhs);
    constraints.distribute(fresh_solution);

    Vector<double> difference = solution;
    difference -= fresh_solution;
    const double relative_difference = difference.linfty_norm() / fresh_solution.linfty_norm();

    const auto  &statistics    = solver.statistics();
    const double flop_fraction = statistics.flops_recomputed / statistics.flops;
    const double time_fraction = seconds / fresh_seconds;
    std::cout << "Step " << step << ": " << n_changed_cells << " cells damaged, " << changed_rows.size()
              << " rows changed" << std::endl
              << "   partial refactorization: " << statistics.columns_recomputed << " of " << statistics.n
              << " columns, " << std::fixed << std::setprecision(1) << 100 * flop_fraction
              << " % of the flops, " << 100 * time_fraction << " % of the time of a full one ("
              << std::setprecision(2) << time_fraction / flop_fraction << " x the flop fraction; "
              << std::setprecision(1) << 1e3 * seconds << " ms against " << 1e3 * fresh_seconds << " ms)"
              << std::endl
              << std::defaultfloat << std::setprecision(2)
              << "   max |x - x_fresh| / max |x_fresh| = " << relative_difference
              << ", max displacement " << solution.linfty_norm() << std::endl;

    partial_flops += statistics.flops_recomputed;
    full_flops += statistics.flops;
    partial_seconds += seconds;
    full_seconds += fresh_seconds;
    largest_difference = std::max(largest_difference, relative_difference);
  }


  template <int dim>
  void ElasticProblem<dim>::run()
  {
    setup_system();
    assemble_system();
    solve(0);
    for (unsigned int step = 1; step <= n_steps; ++step)
      {
        damage_material(step);
        assemble_system();
        solve(step);
      }

    const double flop_fraction = partial_flops / full_flops, time_fraction = partial_seconds / full_seconds;
    std::cout << "All steps: " << std::fixed << std::setprecision(1) << 100 * flop_fraction
              << " % of the flops, " << 100 * time_fraction << " % of the time of full factorizations ("
              << std::setprecision(2) << time_fraction / flop_fraction << " x the flop fraction)" << std::endl
              << std::defaultfloat << "Largest difference to a fresh factorization: " << largest_difference
              << std::endl;
    // The partial refactorization must give the fresh factorization's answers.
    AssertThrow(largest_difference <= 1e-12,
                ExcMessage("a partial refactorization's solution differs from a fresh factorization's"));
  }
} // namespace Step8Partial


int main(int argc, char **argv)
{
  try
    {
      // step-8-partial [cells across the beam] [steps]
      const unsigned int cells_across = argc > 1 ? std::atoi(argv[1]) : 8;
      const unsigned int n_steps      = argc > 2 ? std::atoi(argv[2]) : 5;
      Step8Partial::ElasticProblem<3> elastic_problem(std::max(1u, cells_across), std::max(1u, n_steps));
      elastic_problem.run();
    }
  catch (std::exception &exc)
    {
      std::cerr << std::endl
                << std::endl
                << "----------------------------------------------------" << std::endl;
      std::cerr << "Exception on processing: " << std::endl
                << exc.what() << std::endl
                << "Aborting!" << std::endl
                << "----------------------------------------------------" << std::endl;
      return 1;
    }
  catch (...)
    {
      std::cerr << std::endl
                << std::endl
                << "----------------------------------------------------" << std::endl;
      std::cerr << "Unknown exception!" << std::endl
                << "Aborting!" << std::endl
                << "----------------------------------------------------" << std::endl;
      return 1;
    }

  return 0;
}
