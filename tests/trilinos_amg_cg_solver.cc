// The Trilinos AMG-CG backend on the torus' implicit Euler matrix A = M + dt^2 K (every
// 97th vertex fixed): CG reaches |b - A x| <= tolerance |b| in few iterations, starts from
// the x it is given, and still converges with the preconditioner of the rest matrix after
// the values of A change (a softer material, then every element rotated by a twist of the
// body, as corotation warps them). A system with no unknowns solves to an empty x. Not
// reaching the tolerance, and modes or matrices of the wrong size, are one-line
// MatrixErrors. Iterations are printed against bounds, not as numbers.

#include <warpchol/backends/trilinos_amg_cg.h>
#include <warpchol/dynamics/implicit_euler.h>
#include <warpchol/sparse/residual.h>

#include <deal.II/base/mpi.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

#include <Eigen/Geometry>

#include "tests.h"
#include "torus_elasticity.h"

using namespace warpchol;

namespace
{

  /** b with entries uniform in [-1, 1) (a load, not the image of a known x). */
  std::vector<double> random_right_hand_side(const Index n, const std::uint64_t seed)
  {
    tests::Random       random(seed);
    std::vector<double> b(n);
    for (double &value : b)
      value = 2. * random.uniform() - 1.;
    return b;
  }

  /** Solve from zero, check the residual and print the iterations against @p bound. */
  void solve_and_check(backends::TrilinosAmgCgSolver &solver, const sparse::CSCMatrix &a,
                       const std::vector<double> &b, const double tolerance, const unsigned int bound)
  {
    std::vector<double> x;
    solver.solve(b, x);
    tests::check_below("  |b - A x| / |b|", sparse::relative_residual(a, x, b), tolerance);
    tests::check("  iterations <= " + std::to_string(bound), solver.last_iterations() <= bound);
  }
} // namespace

int main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);

  tests::TorusElasticity   torus;
  const fem::ElasticBody  &body   = *torus.body;
  fem::SystemMatrix       &system = *torus.system;
  const Index              n      = system.size();
  std::cout << "torus: " << n << " unknowns" << std::endl;

  backends::Settings settings;
  settings.backend        = backends::Backend::trilinos_amg_cg;
  settings.tolerance      = 1e-6;
  settings.max_iterations = 200;
  const std::vector<std::vector<double>> modes = fem::rigid_body_modes(body);
  backends::TrilinosAmgCgSolver          solver(settings, modes);
  std::cout << "name: " << solver.name() << std::endl;

  std::cout << "rest matrix:" << std::endl;
  solver.factorize(system.matrix(), system.csc());
  tests::check("  memory_bytes > 0", solver.memory_bytes() > 0);
  const std::vector<double> b = random_right_hand_side(n, 5);
  solve_and_check(solver, system.csc(), b, settings.tolerance, 15);

  // Started from its own solution, CG has nothing left to do.
  std::vector<double> x;
  solver.solve(b, x);
  solver.solve(b, x);
  tests::check("  started from the solution: 0 iterations", solver.last_iterations() == 0);

  // A softer material: the stiffness part halved (a time step 0.7x as long), values only.
  // (A much stiffer one would need a new hierarchy: see TrilinosAmgCgSolver.)
  std::cout << "stiffness 0.5x, preconditioner of the rest matrix:" << std::endl;
  fem::SystemCoefficients softer = torus.coefficients;
  softer.stiffness *= 0.5;
  system.assemble([&](const unsigned int e, fem::ElementMatrix &m) { m = fem::rest_element_matrix(body, e, softer); });
  solver.factorize(system.matrix(), system.csc());
  solve_and_check(solver, system.csc(), b, settings.tolerance, 15);

  // Every element rotated as a twist of the body about the x axis (0.8 rad at either end,
  // 92 degrees from end to end), as corotation warps the element blocks of a deformed body.
  std::cout << "twisted body, preconditioner of the rest matrix:" << std::endl;
  std::array<fem::Matrix3, 4> identity;
  identity.fill(fem::Matrix3::Identity());
  system.assemble([&](const unsigned int e, fem::ElementMatrix &m) {
    fem::Vector3 centroid = fem::Vector3::Zero();
    for (const unsigned int v : body.element_vertices(e))
      centroid += body.rest_positions()[v] / 4.;
    const fem::Matrix3 rotation = Eigen::AngleAxisd(2. * centroid.x(), fem::Vector3::UnitX()).toRotationMatrix();
    m = fem::warped_element_matrix(body, e, torus.coefficients, identity, rotation);
  });
  solver.factorize(system.matrix(), system.csc());
  solve_and_check(solver, system.csc(), b, settings.tolerance, 20);

  std::cout << "tolerance 1e-3:" << std::endl;
  backends::Settings loose = settings;
  loose.tolerance          = 1e-3;
  backends::TrilinosAmgCgSolver loose_solver(loose, modes);
  loose_solver.factorize(system.matrix(), system.csc());
  solve_and_check(loose_solver, system.csc(), b, loose.tolerance, 10);

  // Every vertex fixed: nothing to set up or solve.
  {
    dealii::SparsityPattern      empty_pattern(0, 0, 0);
    empty_pattern.compress();
    dealii::SparseMatrix<double> empty_matrix(empty_pattern);
    backends::TrilinosAmgCgSolver empty(settings, std::vector<std::vector<double>>(6));
    empty.factorize(empty_matrix, sparse::CSCMatrix::zero(0, 0));
    std::vector<double> y(3, 1.);
    empty.solve({}, y);
    tests::check("no unknowns: empty x, 0 iterations", y.empty() && empty.last_iterations() == 0);
  }

  std::cout << "errors:" << std::endl;
  backends::Settings one_iteration = settings;
  one_iteration.tolerance          = 1e-12;
  one_iteration.max_iterations     = 1;
  backends::TrilinosAmgCgSolver stopped(one_iteration, modes);
  stopped.factorize(system.matrix(), system.csc());
  tests::expect_error("  one iteration to 1e-12", [&] {
    std::vector<double> y;
    stopped.solve(b, y);
  });
  tests::expect_error("  five modes", [&] {
    backends::TrilinosAmgCgSolver(settings, std::vector<std::vector<double>>(modes.begin(), modes.begin() + 5));
  });
  tests::expect_error("  modes of another size", [&] {
    backends::TrilinosAmgCgSolver other(settings, std::vector<std::vector<double>>(6, std::vector<double>(6, 0.)));
    other.factorize(system.matrix(), system.csc());
  });
}
