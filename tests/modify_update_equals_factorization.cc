// SparseCholesky::update() (supernodal, METIS) on bcsstk16 and on a P1 elasticity matrix
// (the tests' torus): for ranks 1 to 64, around the 16-column chunks and the 64-column
// groups of the kernel, an update by C equals a fresh factorization of A + C C^T to 1e-12
// relative (factor and solve residual), and update then downdate by C gives back the
// factor of A to 1e-12. C's columns are placed where the modification's paths differ:
// (a) penalty columns on the dofs of local vertices (a grasp), (b) on the first and last
// columns of supernodes, (c) on the columns of the root supernode (the top separator),
// (d) all on the root (the last column of P^T A P), and (e) dense random columns on
// cliques of A (a vertex's dofs and the neighbours coupled with all of them), so that C
// is not diagonal. modify() with interleaved signs (+ a clique column, - a penalty column
// added before) equals the fresh factorization of A + C_+ C_+^T, up to rank 128 (two
// groups of 64). 2 threads give the bits of 1 thread.

#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/sparse/conversions.h>
#include <warpchol/sparse/matrix_market.h>
#include <warpchol/sparse/residual.h>
#include <warpchol/sparse/spd_perturbation.h>

#include "modification_tests.h"
#include "tests.h"
#include "torus_elasticity.h"

#include <functional>

using namespace warpchol;

namespace
{
  const std::vector<Index> ranks = {1, 2, 3, 8, 9, 16, 17, 31, 32, 33, 64};

  /** t * size / k for t < k: k positions spread over [0, size). */
  Index spread(const Index t, const Index k, const Index size)
  {
    return static_cast<Index>(static_cast<double>(t) * static_cast<double>(size) / static_cast<double>(k));
  }

  /** The columns of C of one placement, for a rank. */
  using Placement = std::function<sparse::CSCMatrix(Index rank)>;

  /** Update a copy of @p base by each placement's C of each rank and compare. */
  void check_updates(const std::string &label, const cholesky::SparseCholesky &base, const sparse::CSCMatrix &matrix,
                     const Placement &placement)
  {
    std::cout << label << ":" << std::endl;
    const sparse::CSCMatrix factor_of_a = base.factor();
    bool                    same_bits   = true;
    for (const Index rank : ranks)
      {
        const sparse::CSCMatrix c       = placement(rank);
        sparse::CSCMatrix       updated = matrix;
        sparse::add_outer_products(updated, c, 1.);
        const cholesky::SparseCholesky fresh = tests::fresh_factorization(base, updated);

        cholesky::SparseCholesky solver = base;
        solver.update(c);
        const std::string prefix = "  rank " + std::to_string(rank) + ": ";
        tests::check_below(prefix + "|L_update - L_fresh| / |L_fresh|",
                           sparse::relative_difference(fresh.factor(), solver.factor()), 1e-12);
        tests::check_below(prefix + "||(A + C C^T) x - b|| / ||b||", tests::solve_residual(solver, updated), 1e-12);

        cholesky::SparseCholesky two_threads = base;
        two_threads.set_thread_count(2);
        two_threads.update(c);
        same_bits = same_bits && tests::same_bits(solver.factor(), two_threads.factor());

        solver.downdate(c);
        tests::check_below(prefix + "update then downdate: |L - L_A| / |L_A|",
                           sparse::relative_difference(factor_of_a, solver.factor()), 1e-12);
      }
    tests::check("  2 threads give the bits of 1 thread (every rank)", same_bits);
  }

  // The checks of one matrix in the order of the .output file: a list, kept in one place.
  void run(const std::string &name, const sparse::CSCMatrix &matrix, const int block_size)
  {
    cholesky::SparseCholesky::Settings settings;
    settings.ordering.method = cholesky::OrderingMethod::metis;
    settings.method          = cholesky::FactorizationMethod::supernodal;
    cholesky::SparseCholesky base(settings);
    base.analyze(matrix);
    base.factorize(matrix);
    const Index               n         = matrix.n_cols;
    const std::vector<Index> &perm      = base.permutation();
    const auto               &structure = base.supernodal_symbolic();
    const sparse::CSCMatrix   full      = sparse::to_full_storage(matrix);
    std::cout << name << ": n = " << n << ", " << structure.n_supernodes() << " supernodes" << std::endl;

    // (a) A grasp: penalty columns on the dofs of vertices around a random one.
    check_updates("(a) penalty columns on the dofs of local vertices", base, matrix, [&](const Index rank) {
      std::vector<Index> dofs = sparse::local_vertex_columns(matrix, block_size, (rank + block_size - 1) / block_size, 3);
      dofs.resize(rank);
      return sparse::penalty_columns(matrix, dofs, 1.);
    });

    // (b) The first and the last column of supernodes all over the tree.
    std::vector<Index> boundaries;
    for (Index s = 0; s < structure.n_supernodes(); ++s)
      {
        boundaries.push_back(structure.first_column[s]);
        if (structure.n_columns(s) > 1)
          boundaries.push_back(structure.first_column[s + 1] - 1);
      }
    check_updates("(b) penalty columns at supernode boundaries", base, matrix, [&](const Index rank) {
      std::vector<Index> columns;
      for (Index t = 0; t < rank; ++t)
        columns.push_back(perm[boundaries[spread(t, rank, static_cast<Index>(boundaries.size()))]]);
      return sparse::penalty_columns(matrix, columns, 1.);
    });

    // (c) The top separator: the root supernode's columns (some twice where the rank exceeds them).
    const Index root = structure.supernode_of[n - 1];
    const Index first_of_root = structure.first_column[root], root_columns = structure.n_columns(root);
    std::cout << "root supernode: " << root_columns << " columns" << std::endl;
    check_updates("(c) penalty columns in the top separator", base, matrix, [&](const Index rank) {
      std::vector<Index> columns;
      for (Index t = 0; t < rank; ++t)
        columns.push_back(perm[first_of_root + (rank <= root_columns ? spread(t, rank, root_columns) : t % root_columns)]);
      return sparse::penalty_columns(matrix, columns, 1.);
    });

    // (d) Every column of C on the root.
    check_updates("(d) every column at the root", base, matrix, [&](const Index rank) {
      return sparse::penalty_columns(matrix, std::vector<Index>(rank, perm[n - 1]), 1. / static_cast<double>(rank));
    });

    // (e) Dense columns on cliques of A: a vertex's dofs and the neighbours coupled with
    // all of them, grown from random columns (those coupled to fewer than 3 left out).
    const auto cliques = [&](const Index rank, const std::uint64_t seed) {
      std::vector<std::vector<Index>> rows;
      for (const Index start : sparse::random_columns(n, 4 * rank, seed))
        {
          std::vector<Index> clique = tests::clique_from(full, start, 12);
          if (clique.size() >= 4 && static_cast<Index>(rows.size()) < rank)
            rows.push_back(std::move(clique));
        }
      return tests::dense_columns(matrix, rows, 0.5, seed);
    };
    {
      const sparse::CSCMatrix c = cliques(64, 5);
      tests::check("(e) 64 cliques of 4 to 12 rows", c.n_cols == 64 && [&] {
        for (Index t = 0; t < c.n_cols; ++t)
          if (c.column_start[t + 1] - c.column_start[t] < 4 || c.column_start[t + 1] - c.column_start[t] > 12)
            return false;
        return true;
      }());
    }
    check_updates("(e) dense random columns on cliques of A", base, matrix,
                  [&](const Index rank) { return cliques(rank, 5); });

    // modify() with interleaved signs: from the factor of A + C_- C_-^T (an update first),
    // + the clique columns, - the penalty columns: the factor of A + C_+ C_+^T.
    std::cout << "modify() with interleaved signs, + (e), - (a) added before:" << std::endl;
    bool same_bits = true;
    for (const Index rank : ranks)
      {
        const sparse::CSCMatrix plus = cliques(rank, 7);
        std::vector<Index>      dofs = sparse::local_vertex_columns(matrix, block_size, (rank + block_size - 1) / block_size, 9);
        dofs.resize(rank);
        const sparse::CSCMatrix minus = sparse::penalty_columns(matrix, dofs, 1.);
        const sparse::CSCMatrix both  = tests::side_by_side(plus, minus, true);
        std::vector<double>     signs;
        for (Index t = 0; t < rank; ++t)
          signs.insert(signs.end(), {1., -1.});
        sparse::CSCMatrix updated = matrix;
        sparse::add_outer_products(updated, plus, 1.);
        const cholesky::SparseCholesky fresh = tests::fresh_factorization(base, updated);

        cholesky::SparseCholesky solver = base;
        solver.update(minus);
        cholesky::SparseCholesky two_threads = solver;
        solver.modify(both, signs);
        two_threads.set_thread_count(2);
        two_threads.modify(both, signs);
        same_bits = same_bits && tests::same_bits(solver.factor(), two_threads.factor());
        const std::string prefix = "  rank " + std::to_string(2 * rank) + ": ";
        tests::check_below(prefix + "|L_modify - L_fresh| / |L_fresh|",
                           sparse::relative_difference(fresh.factor(), solver.factor()), 1e-12);
        tests::check_below(prefix + "||(A + C_+ C_+^T) x - b|| / ||b||", tests::solve_residual(solver, updated), 1e-12);
      }
    tests::check("  2 threads give the bits of 1 thread (every rank)", same_bits);
  }
} // namespace

int main()
{
  run("bcsstk16", sparse::read_matrix_market(tests::data_file("bcsstk16.mtx")), 3);
  const tests::TorusElasticity torus;
  run("torus (P1 elasticity)", torus.system->csc(), 3);
}
