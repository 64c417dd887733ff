// SparseDirectCholesky's vmult() on one factor from several threads at once, as its class
// documentation allows ("Threads": vmult(), Tvmult() and solve() are const and may run
// concurrently). Four std::threads each solve their own right-hand sides, with the
// solver's triangular solves serial and tree-parallel (TBB, two threads), and every answer
// equals, to the bit, the one a single thread computed before. Run by the ThreadSanitizer
// stage (.ci/sanitize) too, where a const call that writes (as the solve time once
// written into the statistics) is reported as a data race.

#include <warpchol/lac/sparse_direct_cholesky.h>

#include <deal.II/base/multithread_info.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <cmath>
#include <thread>

#include "tests.h"

using namespace dealii;
using warpchol::SparseDirectCholesky;

namespace
{
  constexpr unsigned int n_callers         = 4;
  constexpr unsigned int solves_per_caller = 6;

  /**
   * The 7-point Laplacian on a k^3 grid plus a shift, assembled without deal.II's finite
   * elements, and small enough (k^3 < 4096) that deal.II's vector operations stay serial:
   * deal.II's own tasks, run by its code, which is not instrumented, would be seen by TSan
   * as races of deal.II's.
   */
  void laplacian(const unsigned int k, SparsityPattern &pattern, SparseMatrix<double> &matrix)
  {
    const auto index = [k](unsigned int x, unsigned int y, unsigned int z) { return (z * k + y) * k + x; };
    DynamicSparsityPattern dynamic(k * k * k);
    const auto for_each_coupling = [&](const auto &visit) {
      for (unsigned int z = 0; z < k; ++z)
        for (unsigned int y = 0; y < k; ++y)
          for (unsigned int x = 0; x < k; ++x)
            {
              const unsigned int i = index(x, y, z);
              visit(i, i, 6.01);
              if (x > 0)
                visit(i, index(x - 1, y, z), -1.);
              if (x + 1 < k)
                visit(i, index(x + 1, y, z), -1.);
              if (y > 0)
                visit(i, index(x, y - 1, z), -1.);
              if (y + 1 < k)
                visit(i, index(x, y + 1, z), -1.);
              if (z > 0)
                visit(i, index(x, y, z - 1), -1.);
              if (z + 1 < k)
                visit(i, index(x, y, z + 1), -1.);
            }
    };
    for_each_coupling([&](unsigned int i, unsigned int j, double) { dynamic.add(i, j); });
    pattern.copy_from(dynamic);
    matrix.reinit(pattern);
    for_each_coupling([&](unsigned int i, unsigned int j, double value) { matrix.set(i, j, value); });
  }

  /** Right-hand side @p k: entries of both signs, different for each k. */
  Vector<double> rhs(const unsigned int size, const unsigned int k)
  {
    Vector<double> b(size);
    for (unsigned int i = 0; i < size; ++i)
      b(i) = std::sin(0.37 * i + 1.3 * k) + 0.1 * k;
    return b;
  }

  void check_concurrent(const SparseMatrix<double> &matrix, const unsigned int solver_threads)
  {
    SparseDirectCholesky::AdditionalData data;
    data.n_threads = solver_threads;
    SparseDirectCholesky solver;
    solver.initialize(matrix, data);
    const unsigned int n = matrix.m();

    // The answers of one thread, then of several at once on the same factor.
    std::vector<Vector<double>> serial(n_callers * solves_per_caller, Vector<double>(n));
    for (unsigned int k = 0; k < serial.size(); ++k)
      solver.vmult(serial[k], rhs(n, k));
    std::vector<Vector<double>> concurrent(serial.size(), Vector<double>(n));
    std::vector<std::thread>    callers;
    for (unsigned int c = 0; c < n_callers; ++c)
      callers.emplace_back([&, c] {
        for (unsigned int r = 0; r < solves_per_caller; ++r)
          {
            const unsigned int k = c + n_callers * r; // the callers' solves interleave
            if (r % 2 == 0)
              solver.vmult(concurrent[k], rhs(n, k));
            else
              {
                concurrent[k] = rhs(n, k);
                solver.solve(concurrent[k]);
              }
          }
      });
    for (std::thread &caller : callers)
      caller.join();

    bool same = true;
    for (unsigned int k = 0; k < serial.size(); ++k)
      for (unsigned int i = 0; i < n; ++i)
        same = same && concurrent[k](i) == serial[k](i);
    // A x - b by rows, serially (deal.II's vmult would run its own tasks).
    const Vector<double> b = rhs(n, 0);
    Vector<double>       residual(n);
    for (unsigned int i = 0; i < n; ++i)
      {
        double sum = -b(i);
        for (auto entry = matrix.begin(i); entry != matrix.end(i); ++entry)
          sum += entry->value() * serial[0](entry->column());
        residual(i) = sum;
      }
    tests::check("solver on " + std::to_string(solver_threads) + " thread(s), " + std::to_string(n_callers) +
                   " callers, " + std::to_string(serial.size()) + " solves: the same bits as one caller's",
                 same);
    tests::check_below("  residual of the first", residual.l2_norm() / b.l2_norm(), 1e-12);
  }
} // namespace

int main()
{
  // deal.II's own tasks off while it sets the matrix up (SparseMatrix::reinit zeroes in
  // parallel): its code is not instrumented, so TSan would see them race. Then every core
  // again, for the solver's arenas.
  MultithreadInfo::set_thread_limit(1);
  SparsityPattern      pattern;
  SparseMatrix<double> matrix;
  laplacian(12, pattern, matrix);
  MultithreadInfo::set_thread_limit();
  check_concurrent(matrix, 1);
  check_concurrent(matrix, 2);
}
