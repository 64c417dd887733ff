// Delayed refresh of the top supernodes (SparseCholesky::Refresh), on a deal.II elasticity
// matrix and on bcsstk16 (METIS, supernodal, 1 and 2 threads), after perturbing the 3x3
// blocks of a few vertices:
// - Refresh::below_top brings every supernode below the top to the values of a full
//   factorization of the new matrix (1e-13 relative) and keeps every top supernode's old
//   values bit for bit; the stale ones are the top supernodes on the changed columns' paths;
// - a later Refresh::all (with no new change) equals the full factorization and spends
//   exactly the stale flops; none, none, all and below_top, below_top, none, all do too;
//   a below_top with no change keeps the stale supernodes stale;
// - predicted_flops() equals the flops the next refactorize() spends, for every Refresh;
// - a top_flops_fraction of 0 makes below_top identical to all, 1 leaves nothing below;
//   the top is upward-closed and holds at least its fraction of the flops;
// - 1 and 2 threads give the same factor after below_top: bit for bit below the top, to
//   rounding (1e-14) in the top, which keeps the values of the first full factorization;
// - column by column, none, none, all equals a full factorization, predicted flops too;
// - a stale factor still solves to a finite vector, an exact one to residual 1e-12;
// - below_top with another method than the supernodal one is an InputError.

#include <warpchol/cholesky/partial.h>
#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/system_matrix.h>
#include <warpchol/mesh/mesh_generators.h>
#include <warpchol/sparse/matrix_market.h>
#include <warpchol/sparse/residual.h>
#include <warpchol/sparse/spd_perturbation.h>

#include "tests.h"
#include "torus_elasticity.h"

using namespace warpchol;
using cholesky::Refresh;

namespace
{
  /** The entries of L in the columns of supernode @p s (factor() stores them contiguously). */
  std::vector<double> supernode_entries(const sparse::CSCMatrix &l, const cholesky::SupernodalSymbolic &structure,
                                        const Index s)
  {
    return {l.values.begin() + l.column_start[structure.first_column[s]],
            l.values.begin() + l.column_start[structure.first_column[s + 1]]};
  }

  /** ||a - b|| / ||b|| (Euclidean). */
  double relative_difference(const std::vector<double> &a, const std::vector<double> &b)
  {
    double difference = 0, norm = 0;
    for (std::size_t k = 0; k < b.size(); ++k)
      {
        difference += (a[k] - b[k]) * (a[k] - b[k]);
        norm += b[k] * b[k];
      }
    return std::sqrt(difference / norm);
  }

  bool same_flops(const double predicted, const double spent)
  {
    return std::abs(predicted - spent) <= 1e-12 * std::max(1., std::abs(spent));
  }

  /** The columns of a few neighbouring vertices (3x3 blocks), perturbed keeping A SPD. */
  std::vector<Index> perturb_vertices(sparse::CSCMatrix &matrix, const std::uint64_t seed)
  {
    const std::vector<Index> changed = sparse::local_vertex_columns(matrix, 3, 4, seed);
    sparse::perturb_columns_spd(matrix, changed, seed);
    return changed;
  }

  /** refactorize(), after checking that predicted_flops() foresees what it spends. */
  void refactorize(const std::string &label, cholesky::SparseCholesky &solver, const sparse::CSCMatrix &matrix,
                   const std::vector<Index> &changed, const Refresh refresh)
  {
    const double predicted = solver.predicted_flops(changed, refresh);
    solver.refactorize(matrix, changed, refresh);
    tests::check("    " + label + ": predicted flops = flops recomputed",
                 same_flops(predicted, solver.statistics().flops_recomputed));
  }

  /** Whether the factor equals a full factorization of @p matrix to 1e-13 relative. */
  void check_equals_full(const std::string &label, const cholesky::SparseCholesky &solver,
                         const sparse::CSCMatrix &matrix)
  {
    cholesky::SparseCholesky full = solver; // same analysis
    full.factorize(matrix);
    tests::check_below("    " + label + ": |L - L_full| / |L_full|",
                       sparse::relative_difference(full.factor(), solver.factor()), 1e-13);
    tests::check("    " + label + ": factor is exact", solver.factor_is_exact());
    const std::vector<double> b = tests::right_hand_side_of_random_solution(matrix, 3);
    std::vector<double>       x;
    solver.solve(b, x);
    tests::check_below("    " + label + ": residual ||Ax-b||/||b||", sparse::relative_residual(matrix, x, b), 1e-12);
  }

  cholesky::SparseCholesky::Settings supernodal_settings(const unsigned int n_threads, const double top_fraction)
  {
    cholesky::SparseCholesky::Settings settings;
    settings.ordering.method    = cholesky::OrderingMethod::metis;
    settings.method             = cholesky::FactorizationMethod::supernodal;
    settings.n_threads          = n_threads;
    settings.top_flops_fraction = top_fraction;
    // Refreshes by recomputation, not the update refactorize() may choose for Refresh::all.
    settings.change_method = cholesky::ChangeMethod::recompute;
    return settings;
  }

  /** The top is upward-closed and holds at least @p fraction of the flops. */
  void check_top(const cholesky::SparseCholesky &solver, const double fraction)
  {
    const auto              &structure = solver.supernodal_symbolic();
    const std::vector<bool> &top       = solver.top_supernodes();
    bool                     upward_closed = true;
    double                   top_flops     = 0;
    for (Index s = 0; s < structure.n_supernodes(); ++s)
      if (top[s])
        {
          const Index parent = structure.supernode_parent[s];
          upward_closed &= parent == -1 || top[parent];
          top_flops += structure.supernode_flops[s];
        }
    const std::string label = "  top for fraction " + format_number(fraction, 2);
    tests::check(label + ": upward-closed", upward_closed);
    tests::check(label + ": holds at least the fraction of the flops",
                 top_flops >= fraction * structure.flops * (1. - 1e-12) &&
                   same_flops(top_flops, solver.statistics().top_flops));
  }

  /** The factor right after a Refresh::below_top, and the entries of its supernodes below the top. */
  struct BelowTopFactor
  {
    sparse::CSCMatrix   factor;
    std::vector<double> below_top_entries;
  };

  /**
   * The refresh sequence on @p matrix (a copy is changed) with @p n_threads threads; returns
   * the factor right after the first Refresh::below_top.
   */
  BelowTopFactor refresh_sequence(const std::string &name, sparse::CSCMatrix matrix, const unsigned int n_threads)
  {
    std::cout << name << ", metis, supernodal, " << n_threads << " thread(s):" << std::endl;
    cholesky::SparseCholesky solver(supernodal_settings(n_threads, 0.5));
    solver.factorize(matrix);
    const auto &structure = solver.supernodal_symbolic();
    const auto &stats     = solver.statistics();
    const auto &top       = solver.top_supernodes();
    std::cout << "  top: " << format_number(stats.top_flops / stats.flops, 2) << " of the flops" << std::endl;
    check_top(solver, 0.5);

    std::cout << "  below_top:" << std::endl;
    const sparse::CSCMatrix  old_factor = solver.factor();
    const std::vector<Index> changed    = perturb_vertices(matrix, 1);
    refactorize("below_top", solver, matrix, changed, Refresh::below_top);
    const sparse::CSCMatrix below_top_factor = solver.factor();
    cholesky::SparseCholesky full = solver;
    full.factorize(matrix);
    const sparse::CSCMatrix full_factor = full.factor();

    // The stale supernodes, found here from the elimination tree: the top ones on the paths
    // from the changed columns.
    const std::vector<Index> inverse = cholesky::invert_permutation(solver.permutation());
    std::vector<Index>       permuted_changed;
    for (const Index j : changed)
      permuted_changed.push_back(inverse[j]);
    std::vector<bool> on_paths(structure.n_supernodes(), false);
    for (const Index j : cholesky::etree_closure(solver.elimination_tree(), permuted_changed))
      on_paths[structure.supernode_of[j]] = true;
    double              largest_below_difference = 0;
    bool                top_unchanged            = true;
    Index               n_stale                  = 0;
    std::vector<double> below_top_entries;
    for (Index s = 0; s < structure.n_supernodes(); ++s)
      {
        const std::vector<double> entries = supernode_entries(below_top_factor, structure, s);
        if (top[s])
          {
            top_unchanged &= entries == supernode_entries(old_factor, structure, s);
            n_stale += on_paths[s] ? 1 : 0;
          }
        else
          {
            largest_below_difference =
              std::max(largest_below_difference, relative_difference(entries, supernode_entries(full_factor, structure, s)));
            below_top_entries.insert(below_top_entries.end(), entries.begin(), entries.end());
          }
      }
    tests::check_below("    every supernode below the top: |L_s - L_full,s| / |L_full,s|", largest_below_difference,
                       1e-13);
    tests::check("    every top supernode keeps its old values bit for bit", top_unchanged);
    tests::check("    stale supernodes = top supernodes on the changed columns' paths, > 0",
                 stats.stale_supernodes == n_stale && n_stale > 0);
    tests::check("    factor is not exact", !solver.factor_is_exact());
    const std::vector<double> b = tests::right_hand_side_of_random_solution(matrix, 2);
    std::vector<double>       x;
    solver.solve(b, x);
    tests::check("    solve with the stale factor gives a finite vector",
                 std::all_of(x.begin(), x.end(), [](const double v) { return std::isfinite(v); }));

    std::cout << "  then all, no new change:" << std::endl;
    const double stale_flops = stats.stale_flops;
    refactorize("all", solver, matrix, {}, Refresh::all);
    tests::check("    flops recomputed = stale flops before", same_flops(stale_flops, stats.flops_recomputed));
    tests::check("    no stale supernode left", stats.stale_supernodes == 0 && stats.stale_flops == 0.);
    check_equals_full("all", solver, matrix);

    std::cout << "  none, none, all:" << std::endl;
    const sparse::CSCMatrix exact_factor = solver.factor();
    refactorize("none", solver, matrix, perturb_vertices(matrix, 2), Refresh::none);
    refactorize("none", solver, matrix, perturb_vertices(matrix, 3), Refresh::none);
    tests::check("    none recomputes nothing and keeps L bit for bit",
                 stats.flops_recomputed == 0. && solver.factor().values == exact_factor.values);
    tests::check("    factor is not exact, changes pending", !solver.factor_is_exact() && stats.pending_columns > 0);
    refactorize("all", solver, matrix, {}, Refresh::all);
    check_equals_full("all", solver, matrix);

    std::cout << "  below_top, below_top with no change, below_top, none, all:" << std::endl;
    refactorize("below_top", solver, matrix, perturb_vertices(matrix, 4), Refresh::below_top);
    const Index stale_supernodes = stats.stale_supernodes;
    const double stale_flops_before = stats.stale_flops;
    refactorize("below_top", solver, matrix, {}, Refresh::below_top);
    tests::check("    with no change the stale supernodes stay stale",
                 stats.stale_supernodes == stale_supernodes && stats.stale_flops == stale_flops_before &&
                   stats.flops_recomputed == 0.);
    refactorize("below_top", solver, matrix, perturb_vertices(matrix, 12), Refresh::below_top);
    refactorize("none", solver, matrix, perturb_vertices(matrix, 5), Refresh::none);
    refactorize("all", solver, matrix, {}, Refresh::all);
    check_equals_full("all", solver, matrix);

    std::cout << "  a change found while loading, then all:" << std::endl;
    refactorize("below_top", solver, matrix, perturb_vertices(matrix, 6), Refresh::below_top);
    perturb_vertices(matrix, 7);
    solver.refactorize(matrix, {}, Refresh::none); // the unlisted change becomes pending
    refactorize("all", solver, matrix, {}, Refresh::all);
    check_equals_full("all", solver, matrix);
    return {below_top_factor, below_top_entries};
  }

  /** Top fractions 0 (below_top is all) and 1 (nothing below the top). */
  void extreme_fractions(const std::string &name, sparse::CSCMatrix matrix)
  {
    std::cout << name << ", top_flops_fraction 0 and 1:" << std::endl;
    cholesky::SparseCholesky below_top(supernodal_settings(1, 0.)), all(supernodal_settings(1, 0.)),
      everything_top(supernodal_settings(1, 1.));
    for (cholesky::SparseCholesky *solver : {&below_top, &all, &everything_top})
      solver->factorize(matrix);
    check_top(below_top, 0.);
    check_top(everything_top, 1.);
    tests::check("  fraction 0: the top is empty", below_top.statistics().n_top_supernodes == 0);
    tests::check("  fraction 1: the top is every supernode",
                 everything_top.statistics().n_top_supernodes == everything_top.statistics().n_supernodes);

    const std::vector<Index> changed = perturb_vertices(matrix, 8);
    below_top.refactorize(matrix, changed, Refresh::below_top);
    all.refactorize(matrix, changed, Refresh::all);
    tests::check("  fraction 0: below_top gives the factor of all bit for bit, exact",
                 below_top.factor().values == all.factor().values && below_top.factor_is_exact());
    const double predicted = everything_top.predicted_flops(changed, Refresh::below_top);
    everything_top.refactorize(matrix, changed, Refresh::below_top);
    tests::check("  fraction 1: below_top recomputes nothing (and predicts it)",
                 everything_top.statistics().flops_recomputed == 0. && predicted == 0. &&
                   everything_top.statistics().stale_supernodes > 0);
  }

  sparse::CSCMatrix elasticity_matrix()
  {
    return tests::TorusElasticity().system->csc();
  }
} // namespace

int main()
{
  const std::vector<std::pair<std::string, sparse::CSCMatrix>> matrices = {
    {"torus elasticity", elasticity_matrix()},
    {"bcsstk16", sparse::read_matrix_market(tests::data_file("bcsstk16.mtx"))}};
  for (const auto &[name, matrix] : matrices)
    {
      const BelowTopFactor one_thread  = refresh_sequence(name, matrix, 1);
      const BelowTopFactor two_threads = refresh_sequence(name, matrix, 2);
      std::cout << name << ", 1 and 2 threads after below_top:" << std::endl;
      tests::check("  the supernodes below the top are identical bit for bit",
                   one_thread.below_top_entries == two_threads.below_top_entries);
      // The top keeps the values of the first, full factorization, where 2 threads split the
      // largest supernodes into blocks: equal to rounding (as in supernodal_factor).
      tests::check_below("  |L_2threads - L_1thread| / |L|",
                         sparse::relative_difference(one_thread.factor, two_threads.factor), 1e-14);
      extreme_fractions(name, matrix);
    }

  // Column by column, none then all works the same way (no top: below_top is refused).
  std::cout << "random SPD n=1000, amd, left-looking:" << std::endl;
  sparse::CSCMatrix                  matrix = tests::random_spd(1000, 3, 5);
  cholesky::SparseCholesky::Settings settings;
  settings.ordering.method = cholesky::OrderingMethod::amd;
  settings.method          = cholesky::FactorizationMethod::left_looking;
  cholesky::SparseCholesky left(settings);
  left.factorize(matrix);
  refactorize("none", left, matrix, perturb_vertices(matrix, 9), Refresh::none);
  refactorize("none", left, matrix, perturb_vertices(matrix, 10), Refresh::none);
  refactorize("all", left, matrix, perturb_vertices(matrix, 11), Refresh::all);
  check_equals_full("all", left, matrix);

  std::cout << "bad input:" << std::endl;
  tests::expect_error("below_top with the left-looking method", [] {
    const sparse::CSCMatrix            matrix = tests::random_spd(100, 3, 1);
    cholesky::SparseCholesky::Settings settings;
    settings.method = cholesky::FactorizationMethod::left_looking;
    cholesky::SparseCholesky solver(settings);
    solver.factorize(matrix);
    solver.refactorize(matrix, {1}, Refresh::below_top);
  });
}
