// SparseDirectCholesky on a TrilinosWrappers::SparseMatrix held by one process: its
// factor equals the one of the same dealii::SparseMatrix (vmult on Trilinos vectors
// gives the deal.II vectors' answer bit for bit), refactorize() from a Trilinos matrix
// whose coefficient changed in a disc recomputes part of the columns and equals a fresh
// factorization to 1e-12, whether the solver was initialized from the Trilinos matrix or
// from the deal.II one; a Trilinos matrix of another pattern is refused in one line.

#include <warpchol/lac/sparse_direct_cholesky.h>

#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>

#include "coefficient_problem.h"
#include "tests.h"

using namespace dealii;
using warpchol::SparseDirectCholesky;

namespace
{
  /** The Trilinos copy of @p matrix, every entry of its pattern kept (zeros too). */
  TrilinosWrappers::SparseMatrix trilinos_copy(const SparseMatrix<double> &matrix)
  {
    TrilinosWrappers::SparseMatrix copy;
    copy.reinit(matrix, 0., true, &matrix.get_sparsity_pattern());
    return copy;
  }

  TrilinosWrappers::MPI::Vector trilinos_copy(const Vector<double> &vector)
  {
    TrilinosWrappers::MPI::Vector copy(complete_index_set(vector.size()), MPI_COMM_SELF);
    for (unsigned int i = 0; i < vector.size(); ++i)
      copy(i) = vector(i);
    copy.compress(VectorOperation::insert);
    return copy;
  }

  /** max_i |x_i - reference_i| / max |reference|, over a Trilinos and a deal.II vector. */
  double relative_difference(const TrilinosWrappers::MPI::Vector &x, const Vector<double> &reference)
  {
    double difference = 0;
    for (unsigned int i = 0; i < reference.size(); ++i)
      difference = std::max(difference, std::abs(x(i) - reference(i)));
    return difference / reference.linfty_norm();
  }
} // namespace

int main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);

  const tests::CoefficientProblem problem(5);
  const tests::Disc               disc{Point<2>(0.2, 0.6), 0.1};
  SparseMatrix<double>            matrix, changed;
  problem.assemble(matrix, 1., disc);
  problem.assemble(changed, 50., disc);
  const auto                 rows             = problem.rows_in(disc);
  const Vector<double>       b                = problem.rhs();
  const auto                 trilinos_matrix  = trilinos_copy(matrix);
  const auto                 trilinos_changed = trilinos_copy(changed);
  const auto                 trilinos_b       = trilinos_copy(b);
  TrilinosWrappers::MPI::Vector trilinos_x(trilinos_b);

  SparseDirectCholesky from_trilinos, from_dealii;
  from_trilinos.initialize(trilinos_matrix);
  from_dealii.initialize(matrix);
  Vector<double> x(b.size());
  from_dealii.vmult(x, b);
  from_trilinos.vmult(trilinos_x, trilinos_b);
  std::cout << "unknowns: " << from_trilinos.m() << std::endl;
  tests::check("initialized from Trilinos: the deal.II matrix's answer, bit for bit",
               relative_difference(trilinos_x, x) == 0.);
  from_trilinos.Tvmult(trilinos_x, trilinos_b);
  tests::check("Tvmult on Trilinos vectors: the same", relative_difference(trilinos_x, x) == 0.);

  SparseDirectCholesky fresh;
  fresh.initialize(changed);
  Vector<double> x_fresh(b.size());
  fresh.vmult(x_fresh, b);
  for (auto *solver : {&from_trilinos, &from_dealii})
    {
      std::cout << (solver == &from_trilinos ? "initialized from Trilinos" : "initialized from deal.II")
                << ", refactorized from Trilinos:" << std::endl;
      solver->refactorize(trilinos_changed, rows);
      const auto &stats = solver->statistics();
      tests::check("  recomputes some of the columns, not all",
                   stats.columns_recomputed > 0 && stats.columns_recomputed < stats.n);
      trilinos_x = trilinos_b;
      solver->solve(trilinos_x);
      tests::check_below("  max |x - x_fresh| / max |x_fresh|", relative_difference(trilinos_x, x_fresh), 1e-12);
    }

  std::cout << "errors:" << std::endl;
  tests::expect_dealii_error<SparseDirectCholesky::ExcInvalidMatrix>("  another pattern", [&] {
    const tests::CoefficientProblem finer(4);
    SparseMatrix<double>            other;
    finer.assemble(other, 1., disc);
    from_trilinos.refactorize(trilinos_copy(other), {0});
  });
}
