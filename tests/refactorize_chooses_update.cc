// refactorize(A', changed) with each ChangeMethod (supernodal, METIS, the tests' P1
// elasticity torus) on changes of A a step would make: a penalty on the 9 dofs of 3
// vertices (a grasp), its removal (a downdate), and a random SPD change of the block of 2
// vertices' dofs (not diagonal). automatic, by_flops, recompute and update all give the
// factor of a fresh factorization of A' to 1e-12; ChangeMethod::update takes every change
// as an update and recompute as a partial refactorization; automatic takes one of the
// two; by_flops's choice, which does not depend on measured times, is printed.

#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/sparse/residual.h>
#include <warpchol/sparse/spd_perturbation.h>

#include "modification_tests.h"
#include "tests.h"
#include "torus_elasticity.h"

using namespace warpchol;

int main()
{
  const tests::TorusElasticity torus;
  const sparse::CSCMatrix     &matrix = torus.system->csc();

  // The steps: (label, new matrix, changed columns).
  const tests::GraspThenPerturbation change(matrix);
  const auto                        &steps = change.steps;

  for (const auto change_method : {cholesky::ChangeMethod::automatic, cholesky::ChangeMethod::by_flops,
                                   cholesky::ChangeMethod::recompute, cholesky::ChangeMethod::update})
    {
      std::cout << "ChangeMethod " << cholesky::to_string(change_method) << ":" << std::endl;
      cholesky::SparseCholesky::Settings settings;
      settings.ordering.method = cholesky::OrderingMethod::metis;
      settings.method          = cholesky::FactorizationMethod::supernodal;
      settings.change_method   = change_method;
      cholesky::SparseCholesky solver(settings);
      solver.analyze(matrix);
      solver.factorize(matrix);
      for (const auto &[label, changed_matrix, changed_columns] : steps)
        {
          solver.refactorize(*changed_matrix, changed_columns);
          const cholesky::RefactorizationMethod method = solver.statistics().method;
          std::cout << "  " << label << " (" << changed_columns.size() << " columns)";
          if (change_method == cholesky::ChangeMethod::by_flops)
            std::cout << ": " << cholesky::to_string(method);
          std::cout << std::endl;
          tests::check_below("    |L - L_fresh| / |L_fresh|",
                             sparse::relative_difference(tests::fresh_factorization(solver, *changed_matrix).factor(),
                                                         solver.factor()),
                             1e-12);
          tests::check_below("    ||A' x - b|| / ||b||", tests::solve_residual(solver, *changed_matrix), 1e-12);
          switch (change_method)
            {
              case cholesky::ChangeMethod::update:
                tests::check("    method: update", method == cholesky::RefactorizationMethod::update);
                break;
              case cholesky::ChangeMethod::recompute:
                tests::check("    method: partial", method == cholesky::RefactorizationMethod::partial);
                break;
              case cholesky::ChangeMethod::automatic:
                tests::check("    method: update or partial", method == cholesky::RefactorizationMethod::update ||
                                                                 method == cholesky::RefactorizationMethod::partial);
                break;
              case cholesky::ChangeMethod::by_flops:
                break;
            }
          if (change_method != cholesky::ChangeMethod::recompute)
            tests::check("    the choice was weighed (predictions positive)",
                         solver.statistics().predicted_update_seconds > 0 &&
                           solver.statistics().predicted_partial_seconds > 0);
        }
    }
}
