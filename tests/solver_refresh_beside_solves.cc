// The background refresh's use of the solver (models/background_refresh.cc), on the
// solver alone: a copy of an analyzed SparseCholesky factors a changed matrix on a
// std::thread of its own (one thread) while the original keeps solving on the calling
// thread (tree-parallel, two TBB threads); then the two are swapped, as
// BackgroundRefresh::take() swaps them, and both go on. The copies share nothing they
// write: every solve gives the bits of a solver that ran alone, and the swapped-in factor
// those of a fresh factorization of the changed matrix. Run by the ThreadSanitizer stage
// too (.ci/sanitize), where a buffer the copies shared would be reported.

#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/sparse/matrix_market.h>

#include <thread>
#include <utility>

#include "tests.h"

using namespace warpchol;

namespace
{
  std::vector<double> solved(const cholesky::SparseCholesky &solver, const std::vector<double> &b)
  {
    std::vector<double> x;
    solver.solve(b, x);
    return x;
  }
} // namespace

int main()
{
  const sparse::CSCMatrix matrix = sparse::read_matrix_market(tests::data_file("bcsstk16.mtx"));
  sparse::CSCMatrix       changed = matrix;
  for (Index j = 0; j < changed.n_cols; ++j) // a stiffer diagonal: the refresh's new values
    changed.values[changed.column_start[j]] *= 1.5;
  const std::vector<double> b = tests::right_hand_side_of_random_solution(matrix, 7);

  cholesky::SparseCholesky::Settings settings;
  settings.n_threads = 2;
  cholesky::SparseCholesky steps(settings);
  steps.analyze(matrix);
  steps.factorize(matrix);
  const std::vector<double> alone = solved(steps, b);

  // The refresh: a copy made from the analyzed solver, factoring on a thread of its own.
  cholesky::SparseCholesky refresh = steps;
  refresh.set_thread_count(1);
  std::thread worker([&] { refresh.factorize(changed); });
  bool same_beside = true;
  for (int k = 0; k < 20; ++k)
    same_beside = same_beside && solved(steps, b) == alone;
  worker.join();
  tests::check("20 solves beside a refresh on another thread: the bits of the solver alone", same_beside);

  // take(): swap, each keeping its thread count, then both solve.
  std::swap(steps, refresh);
  steps.set_thread_count(2);
  refresh.set_thread_count(1);
  // A fresh factorization on one thread, as the refresh's (two give the same L only to
  // rounding), solving on two as the steps do.
  cholesky::SparseCholesky fresh(settings);
  fresh.set_thread_count(1);
  fresh.analyze(changed);
  fresh.factorize(changed);
  fresh.set_thread_count(2);
  tests::check("the refreshed factor, swapped in, solves as a fresh factorization of the changed matrix",
               solved(steps, b) == solved(fresh, b));
  tests::check("the old factor, swapped out, still solves as before", solved(refresh, b) == alone);
}
