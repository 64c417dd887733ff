// The solver on a P1 tetrahedral elasticity matrix assembled with deal.II (a torus, implicit
// Euler matrix A = M + dt^2 K, a few vertices fixed): left-looking L equals up-looking L,
// CHOLMOD's L (same permutation) and the supernodal L to 1e-12 relative; residuals below
// 1e-12; after warping the matrices of a random set of elements (as warp-canceling
// corotation updates them) the partial refactorization, column by column and supernodal
// with 1 and 2 threads, equals a full factorization to 1e-13 and recomputes exactly the
// elimination-tree closure of the changed columns.

#include <warpchol/backends/cholmod_reference.h>
#include <warpchol/cholesky/partial.h>
#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/system_matrix.h>
#include <warpchol/mesh/mesh_generators.h>
#include <warpchol/sparse/residual.h>

#include <Eigen/Geometry>

#include "tests.h"
#include "torus_elasticity.h"

using namespace warpchol;

int main()
{
  const tests::TorusElasticity   torus;
  const fem::ElasticBody        &body         = *torus.body;
  const fem::SystemCoefficients &coefficients = torus.coefficients;
  const sparse::CSCMatrix       &a            = torus.system->csc();
  std::cout << "torus: " << body.n_vertices() << " vertices, " << body.n_elements() << " tets, " << a.n_cols
            << " unknowns, " << a.n_nonzeros() << " entries" << std::endl;

  for (const auto ordering : {cholesky::OrderingMethod::amd, cholesky::OrderingMethod::metis})
    {
      std::cout << cholesky::to_string(ordering) << ":" << std::endl;
      cholesky::SparseCholesky::Settings settings;
      settings.ordering.method = ordering;
      settings.method          = cholesky::FactorizationMethod::left_looking;
      cholesky::SparseCholesky left(settings);
      left.factorize(a);
      settings.method = cholesky::FactorizationMethod::up_looking;
      cholesky::SparseCholesky up(settings);
      up.factorize(a);
      settings.method = cholesky::FactorizationMethod::supernodal;
      cholesky::SparseCholesky supernodal(settings);
      supernodal.factorize(a);
      cholesky::CholmodReference cholmod(false);
      cholmod.analyze(a, left.permutation());
      cholmod.factorize(a);

      const auto &stats = left.statistics();
      std::cout << "  vertex block " << stats.vertex_block_size << ", nnz(L) = " << stats.nnz_l << std::endl;
      const sparse::CSCMatrix l = left.factor();
      tests::check_below("  |L_left - L_up| / |L|", sparse::relative_difference(l, up.factor()), 1e-12);
      tests::check_below("  |L_left - L_cholmod| / |L|", sparse::relative_difference(l, cholmod.factor()), 1e-12);
      tests::check_below("  |L_left - L_supernodal| / |L|", sparse::relative_difference(l, supernodal.factor()), 1e-12);
      std::vector<double> b(a.n_cols), x;
      for (Index i = 0; i < a.n_cols; ++i)
        b[i] = std::sin(0.1 * static_cast<double>(i));
      for (const cholesky::SparseCholesky *solver : {&left, &up, &supernodal})
        {
          solver->solve(b, x);
          tests::check_below("  residual (" + cholesky::to_string(solver->settings().method) + ")",
                             sparse::relative_residual(a, x, b), 1e-12);
        }
    }

  // Warp the element matrices of a random set of elements with random rotations, as an
  // update of warp-canceling corotation does, and refactorize partially.
  std::cout << "partial refactorization after element updates:" << std::endl;
  for (const auto method : {cholesky::FactorizationMethod::left_looking, cholesky::FactorizationMethod::supernodal})
    for (const unsigned int n_threads : {1u, 2u})
      {
        if (method == cholesky::FactorizationMethod::left_looking && n_threads == 2)
          continue;
        fem::SystemMatrix warped(body, coefficients);
        warped.assemble([&](const unsigned int e, fem::ElementMatrix &m) { m = fem::rest_element_matrix(body, e, coefficients); });
        cholesky::SparseCholesky::Settings settings;
        settings.method    = method;
        settings.n_threads = n_threads;
        // Partial refactorization itself, not the update refactorize() may choose instead.
        settings.change_method = cholesky::ChangeMethod::recompute;
        cholesky::SparseCholesky solver(settings);
        solver.factorize(warped.csc());

        std::vector<fem::Matrix3> rotation_of(body.n_elements(), fem::Matrix3::Identity());
        tests::Random             random(11);
        for (const unsigned int n_changed : {1u, 5u, 50u, body.n_elements() / 10})
          {
            std::vector<unsigned int> changed_elements;
            for (unsigned int k = 0; k < n_changed; ++k)
              changed_elements.push_back(static_cast<unsigned int>(random.below(body.n_elements())));
            std::sort(changed_elements.begin(), changed_elements.end());
            changed_elements.erase(std::unique(changed_elements.begin(), changed_elements.end()), changed_elements.end());
            for (const unsigned int e : changed_elements)
              rotation_of[e] = Eigen::AngleAxisd(random.uniform() * 3., fem::Vector3(random.uniform(), random.uniform(), 1).normalized())
                                 .toRotationMatrix();
            std::array<fem::Matrix3, 4> identity;
            identity.fill(fem::Matrix3::Identity());
            const auto element_matrix = [&](const unsigned int e, fem::ElementMatrix &m) {
              m = fem::warped_element_matrix(body, e, coefficients, identity, rotation_of[e]);
            };
            const std::vector<Index> changed_columns = warped.reassemble(changed_elements, element_matrix);
            solver.refactorize(warped.csc(), changed_columns);

            cholesky::SparseCholesky full = solver;
            full.factorize(warped.csc());
            std::vector<Index> permuted;
            const std::vector<Index> inverse = cholesky::invert_permutation(solver.permutation());
            for (const Index j : changed_columns)
              permuted.push_back(inverse[j]);
            const auto &stats = solver.statistics();
            std::cout << "  " << cholesky::to_string(method) << ", " << n_threads << " thread(s), " << changed_elements.size()
                      << " elements: " << changed_columns.size() << " changed columns, " << stats.columns_recomputed
                      << " recomputed, flop fraction " << format_number(stats.flops_recomputed / stats.flops, 3)
                      << std::endl;
            tests::check_below("    |L_partial - L_full| / |L_full|", sparse::relative_difference(full.factor(), solver.factor()), 1e-13);
            tests::check("    dirty columns = etree closure of the changed ones",
                         solver.recomputed_columns() == cholesky::etree_closure(solver.elimination_tree(), permuted));
          }
      }
}
