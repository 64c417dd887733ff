// SparseDirectCholesky where deal.II takes a preconditioner or an inverse. Initialized
// from a dealii::SparseMatrix, vmult() solves (residual 1e-12), Tvmult() and solve() in
// place agree with it, and SolverCG converges in one step with it as the preconditioner of
// its own matrix. As the preconditioner of a matrix whose coefficient changed in a disc
// (the factor of the stale one) CG converges in a few of the iterations it needs
// without. refactorize() with the rows of the disc's cells then recomputes part of the
// columns and of the flops, and its answers equal a fresh factorization's to 1e-12 (by
// either method); CG converges in one step again. A change whose rows are not listed is
// found and refactorized as well.

#include <warpchol/lac/sparse_direct_cholesky.h>

#include <deal.II/lac/precondition.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>

#include "coefficient_problem.h"
#include "tests.h"

using namespace dealii;
using warpchol::SparseDirectCholesky;

namespace
{
  double relative_residual(const SparseMatrix<double> &matrix, const Vector<double> &x, const Vector<double> &b)
  {
    Vector<double> residual(b.size());
    matrix.vmult(residual, x);
    residual -= b;
    return residual.l2_norm() / b.l2_norm();
  }

  /** max |x - reference| / max |reference|. */
  double relative_difference(const Vector<double> &x, const Vector<double> &reference)
  {
    Vector<double> difference(x);
    difference -= reference;
    return difference.linfty_norm() / reference.linfty_norm();
  }

  /** CG's iterations to 1e-10 relative on @p matrix x = @p b with @p preconditioner. */
  template <typename Preconditioner>
  unsigned int cg_iterations(const SparseMatrix<double> &matrix, const Vector<double> &b,
                             const Preconditioner &preconditioner)
  {
    SolverControl            control(5000, 1e-10 * b.l2_norm());
    SolverCG<Vector<double>> cg(control);
    Vector<double>           x(b.size());
    cg.solve(matrix, x, b, preconditioner);
    return control.last_step();
  }

  /** Refactorize @p solver (which factored @p before) for @p after and compare with a fresh factorization. */
  void refactorize_and_compare(const std::string &label, SparseDirectCholesky &solver,
                               const SparseDirectCholesky::AdditionalData &data, const SparseMatrix<double> &after,
                               const std::vector<types::global_dof_index> &rows, const Vector<double> &b)
  {
    solver.refactorize(after, rows);
    const auto &stats = solver.statistics();
    std::cout << label << ": " << rows.size() << " rows changed" << std::endl;
    tests::check("  recomputes some of the columns, not all",
                 stats.columns_recomputed > 0 && stats.columns_recomputed < stats.n);
    tests::check("  and some of the flops, not all",
                 stats.flops_recomputed > 0 && stats.flops_recomputed < stats.flops);

    SparseDirectCholesky fresh;
    fresh.initialize(after, data);
    Vector<double> x(b.size()), x_fresh(b.size());
    solver.vmult(x, b);
    fresh.vmult(x_fresh, b);
    tests::check_below("  max |x - x_fresh| / max |x_fresh|", relative_difference(x, x_fresh), 1e-12);
    tests::check_below("  |b - A x| / |b|", relative_residual(after, x, b), 1e-10);
  }
} // namespace

int main()
{
  const tests::CoefficientProblem problem(5);
  const tests::Disc               disc{Point<2>(0.7, 0.3), 0.1};
  SparseMatrix<double>            matrix, stiff_disc, soft_disc;
  problem.assemble(matrix, 1., disc);
  problem.assemble(stiff_disc, 100., disc);
  problem.assemble(soft_disc, 0.01, disc);
  const Vector<double>                         b    = problem.rhs();
  const std::vector<types::global_dof_index> rows = problem.rows_in(disc);

  SparseDirectCholesky solver;
  solver.initialize(matrix);
  std::cout << "unknowns: " << solver.m() << " x " << solver.n() << std::endl;

  std::cout << "as the inverse:" << std::endl;
  Vector<double> x(b.size()), transposed(b.size()), in_place(b);
  solver.vmult(x, b);
  tests::check_below("  vmult: |b - A x| / |b|", relative_residual(matrix, x, b), 1e-12);
  solver.Tvmult(transposed, b);
  tests::check("  Tvmult equals vmult", transposed == x);
  solver.solve(in_place);
  tests::check("  solve() in place equals vmult", in_place == x);

  std::cout << "as SolverCG's preconditioner:" << std::endl;
  tests::check("  of its own matrix: 1 iteration", cg_iterations(matrix, b, solver) == 1);
  const unsigned int plain = cg_iterations(stiff_disc, b, PreconditionIdentity());
  const unsigned int stale = cg_iterations(stiff_disc, b, solver);
  tests::check("  without: more than 50 iterations", plain > 50);
  tests::check("  the stale factor, coefficient 100x in the disc: under a fifth of those", 5 * stale < plain);

  std::cout << "refactorized:" << std::endl;
  refactorize_and_compare("  supernodal, METIS", solver, SparseDirectCholesky::AdditionalData(), stiff_disc, rows, b);
  tests::check("  SolverCG preconditioned by it: 1 iteration", cg_iterations(stiff_disc, b, solver) == 1);

  const SparseDirectCholesky::AdditionalData left_looking(warpchol::cholesky::OrderingMethod::amd,
                                                          warpchol::cholesky::FactorizationMethod::left_looking);
  SparseDirectCholesky column_by_column;
  column_by_column.initialize(matrix, left_looking);
  refactorize_and_compare("  left-looking, AMD", column_by_column, left_looking, stiff_disc, rows, b);

  // The rows are not listed: the solver finds the columns whose values changed.
  solver.refactorize(soft_disc, {});
  solver.vmult(x, b);
  std::cout << "no row listed, coefficient 0.01 in the disc:" << std::endl;
  tests::check("  the disc's columns are recomputed", solver.statistics().columns_recomputed >= static_cast<warpchol::Index>(rows.size()));
  tests::check_below("  |b - A x| / |b|", relative_residual(soft_disc, x, b), 1e-12);
}
