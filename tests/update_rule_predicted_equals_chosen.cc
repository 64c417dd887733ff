// One rule decides whether a change of A is taken as an update of the factor or by
// recomputing its columns (SparseCholesky::weigh_update()): the method predicted_seconds()
// foresees for a change is the one refactorize() then takes, and when it foresees an update
// it predicts the seconds refactorize() weighed. Supernodal, METIS, the tests' P1 elasticity
// torus, ChangeMethod::flops (fixed rates: the same choice on every machine). The changes
// of refactorize_chooses_update (a penalty on 9 dofs, a random change of 2 vertices'
// block, both removed), with the default Settings::max_update_rows and with 6, which lets
// only the 6-row change be an update.

#include <warpchol/cholesky/sparse_cholesky.h>
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

  for (const Index max_update_rows : {Index(600), Index(6)})
    {
      std::cout << "max_update_rows " << max_update_rows << ":" << std::endl;
      cholesky::SparseCholesky::Settings settings;
      settings.ordering.method = cholesky::OrderingMethod::metis;
      settings.change_method   = cholesky::ChangeMethod::by_flops;
      settings.max_update_rows = max_update_rows;
      cholesky::SparseCholesky solver(settings);
      solver.factorize(matrix);
      for (const auto &[label, changed_matrix, changed_columns] : steps)
        {
          cholesky::RefactorizationMethod foreseen  = cholesky::RefactorizationMethod::none;
          const double                    predicted = solver.predicted_seconds(changed_columns, cholesky::Refresh::all,
                                                                               &foreseen);
          solver.refactorize(*changed_matrix, changed_columns);
          const cholesky::SparseCholesky::Statistics &statistics = solver.statistics();
          std::cout << "  " << label << ": foreseen " << cholesky::to_string(foreseen) << ", taken "
                    << cholesky::to_string(statistics.method) << std::endl;
          tests::check("    the same", foreseen == statistics.method);
          if (foreseen == cholesky::RefactorizationMethod::update)
            tests::check("    the update's predicted seconds are those weighed",
                         predicted == statistics.predicted_update_seconds);
          tests::check_below("    ||A' x - b|| / ||b||", tests::solve_residual(solver, *changed_matrix), 1e-12);
        }
    }
}
