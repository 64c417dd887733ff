// SparseCholesky::inverse_block(): the block of A^-1 among a set of unknowns, with the
// columns of L^-1 of the unknowns that stay in the set kept from the call before while
// the factor does not change (a contact step's vertices from step to step). On the tests'
// elasticity torus (METIS, supernodal): the block equals A^-1's from full solves to 1e-10
// relative, whether its columns were solved anew or kept (and then equals the block
// computed anew to 1e-12); an unchanged set keeps every column; a refactorize() that
// changes nothing keeps them, a refactorize() that changes a column, an update() and a
// full factorize() drop them all (factor_revision() changes), and the block then is the new
// matrix's. Columns that outlive the factor's changes (a lagged W) are renewed in single
// precision (G to 1e-5 relative), then kept as they were (in single precision) and new
// ones solved with the new factor, their rows of G to 1e-5 as well; a sliding set of such
// columns, its layers merged in single precision, stays within 1e-5 of G anew. A copy of
// the solver has its revision. An unknown out of range is refused.

#include <warpchol/cholesky/sparse_cholesky.h>

#include "tests.h"
#include "torus_elasticity.h"

#include <algorithm>
#include <cmath>

using namespace warpchol;

namespace
{
  /** The block of A^-1 among @p unknowns, from full solves with @p solver's factor. */
  std::vector<double> block_by_solves(const cholesky::SparseCholesky &solver, const std::vector<Index> &unknowns)
  {
    const Index         n = static_cast<Index>(solver.permutation().size()), m = static_cast<Index>(unknowns.size());
    std::vector<double> x(static_cast<std::size_t>(n) * m, 0.);
    for (Index j = 0; j < m; ++j)
      x[unknowns[j] + static_cast<std::size_t>(j) * n] = 1.;
    solver.solve(x.data(), x.data(), m);
    std::vector<double> block(static_cast<std::size_t>(m) * m);
    for (Index j = 0; j < m; ++j)
      for (Index i = 0; i < m; ++i)
        block[i + static_cast<std::size_t>(j) * m] = x[unknowns[i] + static_cast<std::size_t>(j) * n];
    return block;
  }

  /** Bring @p columns to @p unknowns and check them against full solves; print what was kept. */
  void check_block(const std::string &label, const cholesky::SparseCholesky &solver,
                   const std::vector<Index> &unknowns, cholesky::KeptInverseColumns &columns)
  {
    solver.inverse_block(unknowns, columns);
    std::cout << label << ": " << unknowns.size() << " unknowns, " << columns.kept << " kept, " << columns.solved
              << " solved" << std::endl;
    tests::check_below("  max |G - A^-1 block| / max |A^-1 block|",
                       tests::max_relative_difference(columns.block(), block_by_solves(solver, unknowns)), 1e-10);
    cholesky::KeptInverseColumns fresh;
    solver.inverse_block(unknowns, fresh);
    tests::check_below("  max |G - G anew| / max |G anew|",
                       tests::max_relative_difference(columns.block(), fresh.block()), 1e-12);
  }
} // namespace

int main()
{
  tests::TorusElasticity   torus;
  sparse::CSCMatrix        matrix = torus.system->lower();
  const Index              n      = matrix.n_cols;
  cholesky::SparseCholesky solver = tests::supernodal_metis_solver();
  solver.factorize(matrix);
  std::cout << "torus elasticity: n = " << n << ", " << solver.supernodal_symbolic().n_supernodes() << " supernodes"
            << std::endl;

  // 20 vertices' unknowns; then 14 of them in another order and 8 new vertices.
  tests::Random      random(37);
  std::vector<Index> vertices;
  while (vertices.size() < 28)
    if (const Index v = random.below(n / 3); std::find(vertices.begin(), vertices.end(), v) == vertices.end())
      vertices.push_back(v);
  const auto unknowns_of = [](const std::vector<Index> &of) {
    std::vector<Index> unknowns;
    for (const Index v : of)
      for (Index c = 0; c < 3; ++c)
        unknowns.push_back(3 * v + c);
    return unknowns;
  };
  const std::vector<Index> first(vertices.begin(), vertices.begin() + 20);
  std::vector<Index>       second(vertices.begin() + 6, vertices.end());
  std::reverse(second.begin(), second.begin() + 14);

  cholesky::KeptInverseColumns columns;
  check_block("first set", solver, unknowns_of(first), columns);
  check_block("14 vertices kept, 8 new", solver, unknowns_of(second), columns);
  check_block("the same set again", solver, unknowns_of(second), columns);
  tests::check("a copy of the solver has its factor's revision",
               cholesky::SparseCholesky(solver).factor_revision() == solver.factor_revision());

  solver.refactorize(matrix, {});
  check_block("after a refactorize() of the same values", solver, unknowns_of(second), columns);

  // A stiffer diagonal entry on the first vertex's x unknown.
  const Index changed  = 3 * second.front();
  double      diagonal = 0;
  for (Index p = matrix.column_start[changed]; p < matrix.column_start[changed + 1]; ++p)
    if (matrix.row_index[p] == changed)
      diagonal = matrix.values[p] *= 2;
  solver.refactorize(matrix, {changed});
  check_block("after a refactorize() of a changed column", solver, unknowns_of(second), columns);

  // A spring on the second vertex's y unknown: A + c c^T.
  sparse::CSCMatrix spring = sparse::CSCMatrix::zero(n, 1);
  spring.row_index         = {3 * second[1] + 1};
  spring.values            = {std::sqrt(diagonal)};
  spring.column_start[1]   = 1;
  solver.update(spring);
  check_block("after an update()", solver, unknowns_of(second), columns);

  solver.factorize(matrix);
  check_block("after a factorize()", solver, unknowns_of(second), columns);

  // Columns that outlive the factor's changes (a lagged W): after an update() the same set
  // keeps every column and G as it was, one change behind; the new vertices' columns, and
  // so their block of G, are the factor's as it is.
  cholesky::KeptInverseColumns lagged;
  lagged.outlive_factor_changes = true;
  solver.inverse_block(unknowns_of(first), lagged);
  tests::check("lagged: renewed in single precision", lagged.single_precision);
  const double single_error =
    tests::max_relative_difference(lagged.block(), block_by_solves(solver, unknowns_of(first)));
  std::cout << "  max |G - A^-1 block| / max |A^-1 block| " << (single_error < 1e-5 ? "<= 1e-5" : "> 1e-5")
            << ", > 1e-12 (single, not double): " << (single_error > 1e-12 ? "yes" : "no") << std::endl;
  const std::vector<double> before = lagged.block();
  solver.update(spring);
  solver.inverse_block(unknowns_of(first), lagged);
  tests::check("lagged: the same set after an update() keeps G, one change behind",
               lagged.kept == 60 && lagged.solved == 0 && lagged.factor_changes_behind == 1 &&
                 lagged.block() == before);
  solver.inverse_block(unknowns_of(second), lagged);
  std::cout << "lagged, 14 vertices kept, 8 new: " << lagged.kept << " kept, " << lagged.solved << " solved, "
            << lagged.factor_changes_behind << " change behind" << std::endl;
  cholesky::KeptInverseColumns fresh;
  solver.inverse_block(unknowns_of(second), fresh);
  const std::size_t   m = unknowns_of(second).size(), first_new = m - 24;
  const std::vector<double> lagged_block = lagged.block(), fresh_block = fresh.block();
  std::vector<double>       new_block, new_block_fresh;
  for (std::size_t j = first_new; j < m; ++j)
    for (std::size_t i = first_new; i < m; ++i)
      {
        new_block.push_back(lagged_block[i + j * m]);
        new_block_fresh.push_back(fresh_block[i + j * m]);
      }
  tests::check_below("  the new vertices' block of G against G anew (kept in single precision)",
                     tests::max_relative_difference(new_block, new_block_fresh), 1e-5);
  tests::check("  the kept ones' block differs from G anew (it is the old factor's)",
               tests::max_relative_difference(lagged.block(), fresh.block()) > 1e-8);

  // A sliding set, as a contact patch moves: each call drops two vertices anywhere in it
  // and takes two new ones (or one back that was dropped). The kept columns stay in the layers they were
  // solved in, dropped ones among them, until the layers merge. Then the same with columns
  // that outlive the factor's changes: kept and merged in single precision.
  for (const bool lagged : {false, true})
  {
    cholesky::KeptInverseColumns sliding;
    sliding.group                  = 3;
    sliding.outlive_factor_changes = lagged;
    std::vector<Index>           patch(vertices.begin(), vertices.begin() + 12), gone;
    double                       worst = 0;
    std::size_t                  most_layers = 0, merges = 0, solved = 0, in_place = 0;
    bool                         grouped = true;
    for (unsigned int call = 0; call < 30; ++call)
      {
        for (unsigned int k = 0; k < 2; ++k)
          {
            const auto leaving = patch.begin() + random.below(static_cast<Index>(patch.size()));
            gone.push_back(*leaving);
            patch.erase(leaving);
          }
        if (call % 5 == 4 && std::find(patch.begin(), patch.end(), gone[gone.size() - 5]) == patch.end())
          patch.push_back(gone[gone.size() - 5]); // dropped two calls ago, back
        while (patch.size() < 12)
          if (const Index v = random.below(n / 3); std::find(patch.begin(), patch.end(), v) == patch.end())
            patch.push_back(v);
        const std::size_t layers_before = sliding.layers.size();
        solver.inverse_block(unknowns_of(patch), sliding);
        solved += static_cast<std::size_t>(sliding.solved);
        // New vertices in the places of dropped ones: G's places are not in the order asked.
        bool in_order = true;
        for (std::size_t i = 0; i < sliding.places.size(); ++i)
          in_order = in_order && sliding.places[i] == static_cast<Index>(i);
        for (std::size_t i = 0; i < sliding.places.size(); i += 3)
          grouped = grouped && sliding.places[i] % 3 == 0 && sliding.places[i + 1] == sliding.places[i] + 1 &&
                    sliding.places[i + 2] == sliding.places[i] + 2;
        in_place += in_order ? 0 : 1;
        most_layers = std::max(most_layers, sliding.layers.size());
        merges += sliding.layers.size() == 1 && layers_before > 1 ? 1 : 0;
        cholesky::KeptInverseColumns anew;
        solver.inverse_block(unknowns_of(patch), anew);
        worst = std::max(worst, tests::max_relative_difference(sliding.block(), anew.block()));
      }
    std::cout << "a sliding set of 12 vertices" << (lagged ? ", lagged (single precision)" : "") << ", 30 calls: "
              << solved / 3 << " vertices solved, " << most_layers << " layers at most, " << merges << " merges"
              << std::endl;
    tests::check("  new vertices took dropped ones' places in G, a slot of 3 each", in_place > 10 && grouped);
    tests::check_below("  max over the calls of max |G - G anew| / max |G anew|", worst, lagged ? 1e-5 : 1e-12);
    tests::check("  the layers grew and were merged", most_layers > 2 && merges > 0);
  }

  tests::expect_error("an unknown out of range", [&] { solver.inverse_block({0, n}, columns); });
}
