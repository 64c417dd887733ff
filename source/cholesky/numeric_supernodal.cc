#include <warpchol/base/exceptions.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/cholesky/blas.h>
#include <warpchol/cholesky/numeric_supernodal.h>

#include "scaled_solve.h"
#include "supernode_solve_kernel.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <limits>
#include <mutex>

namespace warpchol::cholesky
{
  namespace
  {
    /** What one thread needs to compute a supernode. */
    struct Workspace
    {
      /** map[row] = position of that row in the supernode being computed. */
      std::vector<Index>  map;
      /** Positions in the target supernode of the rows of one update. */
      std::vector<Index>  relative_map;
      /** The update L_d(rows, :) L_d(cols, :)^T before it is scattered. */
      std::vector<double> update;
      double              flops = 0;

      void reserve(const SupernodalSymbolic &symbolic)
      {
        if (static_cast<Index>(map.size()) < symbolic.n)
          map.resize(symbolic.n);
        if (static_cast<Index>(relative_map.size()) < symbolic.n)
          relative_map.resize(symbolic.n);
        if (static_cast<Index>(update.size()) < symbolic.max_update_size)
          update.resize(symbolic.max_update_size);
      }
    };

    /** Supernodes whose own work exceeds this many flops split it over threads. */
    constexpr double parallel_supernode_flops = 1e7;
    /**
     * An update is computed in blocks of at least this many columns, and of about
     * update_block_doubles entries, so that each block is scattered while still in cache.
     */
    constexpr Index update_block_columns = 32;
    constexpr Index update_block_doubles = 1 << 15;
    /**
     * Updates from descendants at least this wide are compute-bound: one dgemm without
     * column blocking (blocking would repack the descendant's whole panel for every block).
     */
    constexpr Index wide_update = 64;
    /** Column block of the threaded dense Cholesky of a large supernode. */
    constexpr Index panel_block = 256;

    /** Split [begin, end) into about @p n_chunks ranges of equal weight. */
    template <typename Weight>
    std::vector<Index> balanced_chunks(const Index begin, const Index end, const Index n_chunks,
                                       const Weight &weight)
    {
      double total = 0;
      for (Index r = begin; r < end; ++r)
        total += weight(r);
      std::vector<Index> bounds{begin};
      double             accumulated = 0;
      for (Index r = begin; r < end; ++r)
        {
          accumulated += weight(r);
          if (accumulated >= total * static_cast<double>(bounds.size()) / static_cast<double>(n_chunks) &&
              r + 1 < end && static_cast<Index>(bounds.size()) < n_chunks)
            bounds.push_back(r + 1);
        }
      bounds.push_back(end);
      return bounds;
    }

    /**
     * One call of factorize(): the supernodes to compute and how, over a shared value array.
     */
    class NumericRun
    {
    public:
      NumericRun(const SupernodalSymbolic                 &symbolic,
                 const sparse::CSCMatrix                  &lower,
                 double                                   *values,
                 float                                    *seconds_per_flop,
                 tbb::enumerable_thread_specific<Workspace> &workspaces,
                 const unsigned int                        n_threads)
        : symbolic(symbolic)
        , lower(lower)
        , values(values)
        , seconds_per_flop(seconds_per_flop)
        , workspaces(workspaces)
        , n_threads(std::max(1u, n_threads))
      {}

      /** Compute supernodes[k] from column offset offsets[k] (0 if offsets is empty). */
      void run(const std::vector<Index> &supernodes, const std::vector<Index> &offsets)
      {
        const Index ns = symbolic.n_supernodes();
        start_offset.assign(ns, -1);
        if (supernodes.empty())
          for (Index s = 0; s < ns; ++s)
            start_offset[s] = 0;
        else
          for (std::size_t k = 0; k < supernodes.size(); ++k)
            start_offset[supernodes[k]] = offsets.empty() ? 0 : offsets[k];
        selected = supernodes;
        if (selected.empty())
          {
            selected.resize(ns);
            for (Index s = 0; s < ns; ++s)
              selected[s] = s;
          }

        if (n_threads == 1)
          {
            Workspace &workspace = workspaces.local();
            workspace.reserve(symbolic);
            for (const Index s : selected)
              compute_supernode(s, workspace, false);
            return;
          }
        tbb::task_arena arena(static_cast<int>(n_threads));
        arena.execute([&] { run_in_parallel(); });
      }

    private:
      const SupernodalSymbolic                  &symbolic;
      const sparse::CSCMatrix                   &lower;
      double                                    *values;
      /** Per supernode: the seconds per flop of its computations, averaged (SupernodalFactor::timed_seconds()). */
      float                                     *seconds_per_flop;
      tbb::enumerable_thread_specific<Workspace> &workspaces;
      const unsigned int                         n_threads;

      /** start_offset[s]: first column (local) of s to compute, -1 if s is not computed. */
      std::vector<Index> start_offset;
      std::vector<Index> selected;
      /** Tree of the selected supernodes: children lists and the flops of each subtree. */
      std::vector<Index>  child_start, children;
      std::vector<double> subtree_flops;
      double              sequential_cutoff = 0;

      void run_in_parallel()
      {
        const Index ns = symbolic.n_supernodes();
        child_start.assign(ns + 1, 0);
        subtree_flops.assign(ns, 0.);
        std::vector<Index> roots;
        for (const Index s : selected)
          {
            const Index p = symbolic.supernode_parent[s];
            if (p != -1 && start_offset[p] != -1)
              ++child_start[p + 1];
            else
              roots.push_back(s);
          }
        for (Index s = 0; s < ns; ++s)
          child_start[s + 1] += child_start[s];
        children.resize(child_start[ns]);
        std::vector<Index> next(child_start.begin(), child_start.end() - 1);
        double             total = 0;
        for (const Index s : selected) // increasing: children before parents
          {
            subtree_flops[s] += symbolic.supernode_flops[s];
            total += symbolic.supernode_flops[s];
            const Index p = symbolic.supernode_parent[s];
            if (p != -1 && start_offset[p] != -1)
              {
                children[next[p]++] = s;
                subtree_flops[p] += subtree_flops[s];
              }
          }
        // Subtrees below this size run as one sequential task: enough tasks to balance the
        // threads, not so many that scheduling costs show.
        sequential_cutoff = total / (8. * n_threads);
        tbb::task_group group;
        for (const Index root : roots)
          group.run([this, root] { run_subtree(root); });
        group.wait();
      }

      void run_subtree(const Index s)
      {
        if (subtree_flops[s] <= sequential_cutoff)
          {
            Workspace &workspace = workspaces.local();
            workspace.reserve(symbolic);
            // The subtree of s is the range [first_descendant[s], s] of supernodes.
            const auto first = std::lower_bound(selected.begin(), selected.end(), symbolic.first_descendant[s]);
            const auto last  = std::upper_bound(first, selected.end(), s);
            for (auto t = first; t != last; ++t)
              compute_supernode(*t, workspace, false);
            return;
          }
        tbb::task_group group;
        for (Index k = child_start[s]; k < child_start[s + 1]; ++k)
          {
            const Index child = children[k];
            group.run([this, child] { run_subtree(child); });
          }
        group.wait();
        Workspace &workspace = workspaces.local();
        workspace.reserve(symbolic);
        compute_supernode(s, workspace, symbolic.supernode_flops[s] > parallel_supernode_flops);
      }

      /** Compute s from its start offset on, over the threads if @p threaded, and time it (seconds_per_flop). */
      void compute_supernode(const Index s, Workspace &workspace, const bool threaded)
      {
        const Stopwatch stopwatch;
        const Index     q = start_offset[s];
        if (threaded)
          factor_supernode_threaded(s, q, workspace);
        else
          factor_supernode(s, q, workspace);
        const double flops = symbolic.flops_from(s, q);
        if (!(flops > 0))
          return;
        // A moving average, as the cost model's rates: one slow run (a busy machine) does
        // not stand for the supernode until it runs again.
        constexpr float new_weight = 0.3f;
        const float     measured   = static_cast<float>(stopwatch.seconds() / flops);
        float          &average    = seconds_per_flop[s];
        average = average >= 0 ? (1 - new_weight) * average + new_weight * measured : measured;
      }

      double *block(const Index s) const
      {
        return values + symbolic.value_start[s];
      }

      /** Map the rows of s to their positions, clear columns [q, nc) and gather C into them. */
      void gather(const Index s, const Index q, Index *map) const
      {
        const Index  f = symbolic.first_column[s], nc = symbolic.n_columns(s), nr = symbolic.n_rows(s);
        const Index *rows = symbolic.row_index.data() + symbolic.row_start[s];
        for (Index r = 0; r < nr; ++r)
          map[rows[r]] = r;
        double *ls = block(s);
        std::fill(ls + q * nr, ls + nc * nr, 0.);
        for (Index c = q; c < nc; ++c)
          {
            double *column = ls + c * nr;
            for (Index p = lower.column_start[f + c]; p < lower.column_start[f + c + 1]; ++p)
              column[map[lower.row_index[p]]] = lower.values[p];
          }
      }

      /**
       * Subtract from supernode s the part of update k (from a descendant d) that falls in
       * the local columns [column_begin, column_end) of s, rows at and below them:
       *   L_s(rows, cols) -= L_d(rows, :) L_d(cols, :)^T.
       * Straight into the block when d's rows land on consecutive rows of s; otherwise
       * computed (dsyrk + dgemm) and scattered through the row map a block of columns at a
       * time, a block small enough to stay in cache between the dgemm that writes it and
       * the scatter that reads it.
       */
      void apply_update(const Index s, const Index k, const Index column_begin, const Index column_end,
                        const Index *map, Workspace &workspace) const
      {
        const Index  f    = symbolic.first_column[s];
        const Index *rows = symbolic.row_index.data();
        const Index  p1   = symbolic.update_first_row(k, s, column_begin);
        const Index  p2   = std::lower_bound(rows + p1, rows + symbolic.update_row_end[k], f + column_end) - rows;
        if (p1 == p2)
          return;
        const Index   d      = symbolic.update_source[k];
        const Index   end    = symbolic.row_start[d + 1];
        const Index   rows1  = p2 - p1, rows2 = end - p1, width = symbolic.n_columns(d);
        const Index   nr     = symbolic.n_rows(s);
        const int     ld     = static_cast<int>(nr), ldd = static_cast<int>(symbolic.n_rows(d));
        const double *ld_top = block(d) + (p1 - symbolic.row_start[d]);
        double       *ls     = block(s);
        const Index   r0     = map[rows[p1]];
        if (map[rows[end - 1]] - r0 == rows2 - 1)
          {
            double *target = ls + r0 + r0 * nr;
            blas::syrk_lower(rows1, width, -1., ld_top, ldd, 1., target, ld);
            blas::gemm_nt(rows2 - rows1, rows1, width, -1., ld_top + rows1, ldd, ld_top, ldd, 1., target + rows1, ld);
            return;
          }
        Index *relative = workspace.relative_map.data();
        for (Index r = 0; r < rows2; ++r)
          relative[r] = map[rows[p1 + r]];
        // Rows of d within s's columns map to local columns: relative[c] is column c's.
        double     *update = workspace.update.data();
        const Index step =
          width >= wide_update ? rows1 : std::max<Index>(update_block_columns, update_block_doubles / rows2);
        for (Index c0 = 0; c0 < rows1; c0 += step)
          {
            const Index c1 = std::min(c0 + step, rows1), width1 = c1 - c0, m = rows2 - c0;
            blas::syrk_lower(width1, width, 1., ld_top + c0, ldd, 0., update, m);
            blas::gemm_nt(m - width1, width1, width, 1., ld_top + c1, ldd, ld_top + c0, ldd, 0., update + width1, m);
            for (Index c = c0; c < c1; ++c)
              {
                double       *target = ls + relative[c] * nr;
                const double *source = update + (c - c0) * m - c0; // source[r]: row r
                for (Index r = c; r < rows2; ++r)
                  target[relative[r]] -= source[r];
              }
          }
      }

      void factor_supernode(const Index s, const Index q, Workspace &workspace)
      {
        const Index nc = symbolic.n_columns(s), nr = symbolic.n_rows(s);
        const int   ld = static_cast<int>(nr);
        double     *ls = block(s);
        gather(s, q, workspace.map.data());
        for (Index k = symbolic.update_start[s]; k < symbolic.update_start[s + 1]; ++k)
          apply_update(s, k, q, nc, workspace.map.data(), workspace);
        // The columns [0, q) of s already hold L: apply them, then dpotrf and dtrsm.
        if (q > 0)
          {
            blas::syrk_lower(nc - q, q, -1., ls + q, ld, 1., ls + q + q * nr, ld);
            blas::gemm_nt(nr - nc, nc - q, q, -1., ls + nc, ld, ls + q, ld, 1., ls + nc + q * nr, ld);
          }
        check_pivot(s, q, blas::potrf_lower(nc - q, ls + q + q * nr, ld));
        blas::trsm_right_lower_transpose(nr - nc, nc - q, ls + q + q * nr, ld, ls + nc + q * nr, ld);
        workspace.flops += symbolic.flops_from(s, q);
      }

      /** Throw NotPositiveDefinite if dpotrf stopped at the pivot @p info of block column q. */
      void check_pivot(const Index s, const Index column_offset, const int info) const
      {
        if (info == 0)
          return;
        const Index local = column_offset + info - 1;
        const Index nr    = symbolic.n_rows(s);
        throw NotPositiveDefinite(symbolic.first_column[s] + local, block(s)[local + local * nr]);
      }

      /**
       * Local columns [begin, end) of s cut into one range per thread, balanced by the
       * entries at and below the diagonal of each column (its share of update work).
       */
      std::vector<Index> column_ranges(const Index s, const Index begin, const Index end) const
      {
        const Index nr = symbolic.n_rows(s);
        return balanced_chunks(begin, end, static_cast<Index>(n_threads),
                               [nr](const Index c) { return static_cast<double>(nr - c); });
      }

      /**
       * The same as factor_supernode() for a large supernode, its columns split into one
       * range per thread: each thread applies every update to its own columns (no two
       * threads write the same entry, and each entry sums its updates in the same order as
       * the serial code). Then a blocked right-looking dense Cholesky whose triangular solves
       * are split by rows and whose trailing updates are split by columns the same way.
       */
      void factor_supernode_threaded(const Index s, const Index q, Workspace &owner)
      {
        // The row map must outlive the parallel loops below, during which this thread may
        // run other tasks that use its thread-local workspace: it gets its own array.
        const std::unique_ptr<Index[]> shared_map(new Index[symbolic.n]);
        gather(s, q, shared_map.get());
        const Index              nc     = symbolic.n_columns(s), nr = symbolic.n_rows(s);
        const int                ld     = static_cast<int>(nr);
        double                  *ls     = block(s);
        const std::vector<Index> ranges = column_ranges(s, q, nc);
        tbb::parallel_for(Index(0), static_cast<Index>(ranges.size()) - 1, [&](const Index range) {
          Workspace &workspace = workspaces.local();
          workspace.reserve(symbolic);
          for (Index k = symbolic.update_start[s]; k < symbolic.update_start[s + 1]; ++k)
            apply_update(s, k, ranges[range], ranges[range + 1], shared_map.get(), workspace);
        });

        // Trailing update of columns [from, nc) (all rows below them) by columns [k0, k1).
        auto trailing_update = [&](const Index k0, const Index k1, const Index from) {
          if (from >= nc || k1 <= k0)
            return;
          const std::vector<Index> columns = column_ranges(s, from, nc);
          tbb::parallel_for(Index(0), static_cast<Index>(columns.size()) - 1, [&](const Index range) {
            const Index c0 = columns[range], c1 = columns[range + 1];
            blas::syrk_lower(c1 - c0, k1 - k0, -1., ls + c0 + k0 * nr, ld, 1., ls + c0 + c0 * nr, ld);
            blas::gemm_nt(nr - c1, c1 - c0, k1 - k0, -1., ls + c1 + k0 * nr, ld, ls + c0 + k0 * nr, ld, 1.,
                          ls + c1 + c0 * nr, ld);
          });
        };
        trailing_update(0, q, q);
        for (Index k = q; k < nc; k += panel_block)
          {
            const Index kb = std::min(panel_block, nc - k), below = k + kb;
            check_pivot(s, k, blas::potrf_lower(kb, ls + k + k * nr, ld));
            if (below < nr)
              {
                const std::vector<Index> rows =
                  balanced_chunks(below, nr, static_cast<Index>(n_threads), [](Index) { return 1.; });
                tbb::parallel_for(Index(0), static_cast<Index>(rows.size()) - 1, [&](const Index range) {
                  const Index a = rows[range], b = rows[range + 1];
                  blas::trsm_right_lower_transpose(b - a, kb, ls + k + k * nr, ld, ls + a + k * nr, ld);
                });
              }
            trailing_update(k, below, below);
          }
        owner.flops += symbolic.flops_from(s, q);
      }
    };
  } // namespace


  namespace
  {
    /**
     * How a threaded solve splits the supernodal tree: disjoint subtrees (each a range of
     * supernodes [first_descendant[root], root], postorder) that threads solve side by side,
     * and the top above them, solved by one thread. The columns of the top are numbered
     * 0.. in top_position, so that each subtree can gather what it subtracts from them.
     */
    struct SolvePartition
    {
      std::vector<Index> subtree_roots;
      std::vector<Index> top_supernodes;
      /** top_position[column] = position of the column among the top's, -1 if not in the top. */
      std::vector<Index> top_position;
      /** The top's columns, in the order of their positions. */
      std::vector<Index> top_columns;
      Index              n_top_columns = 0;
      /** The threads that solve the subtrees (made once: an arena is costly to start). */
      std::unique_ptr<tbb::task_arena> arena;
    };

    /**
     * Subtrees of the split are at most this share of the stored values (the solve's memory
     * traffic): enough subtrees to balance a few threads, and the same split for any number
     * of them, so that a solve gives the same bits on one thread as on several.
     */
    constexpr double solve_subtree_share = 1. / 16;

    /** Split until the heaviest subtree is at most solve_subtree_share of the whole. */
    SolvePartition partition_for_solve(const SupernodalSymbolic &symbolic, const unsigned int n_threads)
    {
      const Index         ns = symbolic.n_supernodes();
      std::vector<double> weight(ns, 0.);
      std::vector<std::vector<Index>> children(ns);
      std::vector<Index>  roots;
      for (Index s = 0; s < ns; ++s) // children before parents
        {
          weight[s] += static_cast<double>(symbolic.value_start[s + 1] - symbolic.value_start[s]);
          const Index p = symbolic.supernode_parent[s];
          if (p == -1)
            roots.push_back(s);
          else
            {
              weight[p] += weight[s];
              children[p].push_back(s);
            }
        }
      double total = 0;
      for (const Index r : roots)
        total += weight[r];
      const double bound = total * solve_subtree_share;

      SolvePartition partition;
      std::vector<Index> candidates = roots;
      while (!candidates.empty())
        {
          const Index s = candidates.back();
          candidates.pop_back();
          if (weight[s] > bound && !children[s].empty())
            {
              partition.top_supernodes.push_back(s);
              candidates.insert(candidates.end(), children[s].begin(), children[s].end());
            }
          else
            partition.subtree_roots.push_back(s);
        }
      std::sort(partition.top_supernodes.begin(), partition.top_supernodes.end());
      std::sort(partition.subtree_roots.begin(), partition.subtree_roots.end());
      partition.top_position.assign(symbolic.n, -1);
      for (const Index s : partition.top_supernodes)
        for (Index j = symbolic.first_column[s]; j < symbolic.first_column[s + 1]; ++j)
          {
            partition.top_position[j] = partition.n_top_columns++;
            partition.top_columns.push_back(j);
          }
      partition.arena = std::make_unique<tbb::task_arena>(static_cast<int>(std::max(1u, n_threads)));
      return partition;
    }

    /**
     * Forward substitution L y = x on supernode s: dtrsm on its diagonal block, dgemm for
     * the rows below, subtracted from x, or, for the rows @p outside says, from @p gathered
     * (at the position it gives): what a subtree solved by one thread subtracts from the top.
     */
    template <typename Real, typename Outside>
    void forward_supernode(const SupernodalSymbolic &symbolic, const Real *values, Real *x, const Index n_rhs,
                           const Index s, std::vector<Real> &below, const Outside &outside, Real *gathered,
                           const Index gathered_size)
    {
      const int    n = static_cast<int>(symbolic.n), m = static_cast<int>(n_rhs);
      const Index  f = symbolic.first_column[s], nc = symbolic.n_columns(s), nr = symbolic.n_rows(s);
      const int    rows_below = static_cast<int>(nr - nc);
      const Real  *ls         = values + symbolic.value_start[s];
      const Index *rows       = symbolic.row_index.data() + symbolic.row_start[s];
      if (n_rhs == 1)
        {
          // A right-hand side still zero on the supernode's columns (a sparse one, as a
          // contact correction's) stays zero there and takes nothing from the rows below.
          if (std::all_of(x + f, x + f + nc, [](const Real value) { return value == Real(0); }))
            return;
          // One right-hand side: the supernode's own kernel (supernode_solve_kernel.h),
          // without a BLAS call's set-up per supernode.
          forward_supernode_gathered(symbolic, values, s, x, below);
          // The rows below hold - L21 y_s: what the rows below (or the top's gathered rows) take.
          for (Index i = 0; i < rows_below; ++i)
            {
              const Index position = outside(rows[nc + i]);
              if (position < 0)
                x[rows[nc + i]] += below[nc + i];
              else
                gathered[position] -= below[nc + i];
            }
          return;
        }
      blas::trsm_left_lower(false, static_cast<int>(nc), m, ls, static_cast<int>(nr), x + f, n);
      if (rows_below == 0)
        return;
      below.resize(std::max<std::size_t>(below.size(), static_cast<std::size_t>(rows_below) * n_rhs));
      blas::gemm(false, false, rows_below, m, static_cast<int>(nc), Real(1), ls + nc, static_cast<int>(nr), x + f, n,
                 Real(0), below.data(), rows_below);
      for (Index r = 0; r < n_rhs; ++r)
        for (Index i = 0; i < rows_below; ++i)
          {
            const Index row      = rows[nc + i];
            const Index position = outside(row);
            if (position < 0)
              x[row + r * n] -= below[i + r * rows_below];
            else
              gathered[position + r * gathered_size] += below[i + r * rows_below];
          }
    }

    /** Backward substitution L^T x = y on supernode s: reads the rows below, writes its own. */
    template <typename Real>
    void backward_supernode(const SupernodalSymbolic &symbolic, const Real *values, Real *x, const Index n_rhs,
                            const Index s, std::vector<Real> &below)
    {
      const int    n = static_cast<int>(symbolic.n), m = static_cast<int>(n_rhs);
      const Index  f = symbolic.first_column[s], nc = symbolic.n_columns(s), nr = symbolic.n_rows(s);
      const int    rows_below = static_cast<int>(nr - nc);
      const Real  *ls         = values + symbolic.value_start[s];
      const Index *rows       = symbolic.row_index.data() + symbolic.row_start[s];
      if (n_rhs == 1)
        {
          below.resize(std::max<std::size_t>(below.size(), static_cast<std::size_t>(nr)));
          std::copy(x + f, x + f + nc, below.begin());
          for (Index i = 0; i < rows_below; ++i)
            below[nc + i] = x[rows[nc + i]];
          backward_supernode_double(ls, nr, nc, below.data());
          std::copy(below.begin(), below.begin() + nc, x + f);
          return;
        }
      if (rows_below > 0)
        {
          below.resize(std::max<std::size_t>(below.size(), static_cast<std::size_t>(rows_below) * n_rhs));
          for (Index r = 0; r < n_rhs; ++r)
            for (Index i = 0; i < rows_below; ++i)
              below[i + r * rows_below] = x[rows[nc + i] + r * n];
          blas::gemm(true, false, static_cast<int>(nc), m, rows_below, Real(-1), ls + nc, static_cast<int>(nr),
                     below.data(), rows_below, Real(1), x + f, n);
        }
      blas::trsm_left_lower(true, static_cast<int>(nc), m, ls, static_cast<int>(nr), x + f, n);
    }

    /**
     * Overwrite @p x (n x n_rhs, column-major) with the solution of L L^T z = x by
     * supernodes: forward(s, x, below, outside, gathered, gathered_size) and backward(s, x,
     * below) do one supernode's part (forward_supernode(), backward_supernode()). With
     * @p partition (threads), the subtrees run side by side: in the forward pass each
     * gathers what it subtracts from the top's rows in its own buffer, added in subtree
     * order (deterministic); the top is solved by one thread; in the backward pass each
     * supernode writes only its own rows, so the subtrees run side by side again.
     */
    template <typename Real, typename Forward, typename Backward>
    void solve_by_supernodes(const SupernodalSymbolic &symbolic, Real *x, const Index n_rhs,
                             const SolvePartition *partition, const Forward &forward, const Backward &backward)
    {
      const Index       ns = symbolic.n_supernodes();
      std::vector<Real> below;
      const auto        inside = [](Index) { return Index(-1); };
      if (partition == nullptr)
        {
          for (Index s = 0; s < ns; ++s)
            forward(s, x, below, inside, static_cast<Real *>(nullptr), 0);
          for (Index s = ns - 1; s >= 0; --s)
            backward(s, x, below);
          return;
        }

      const Index                    n_subtrees = static_cast<Index>(partition->subtree_roots.size());
      const Index                    top_size   = partition->n_top_columns;
      std::vector<std::vector<Real>> gathered(n_subtrees);
      tbb::task_arena               &arena = *partition->arena;
      arena.execute([&] {
        tbb::parallel_for(Index(0), n_subtrees, [&](const Index k) {
          std::vector<Real> local_below;
          gathered[k].assign(top_size * n_rhs, Real(0));
          const Index root    = partition->subtree_roots[k];
          const auto  outside = [&](const Index row) { return partition->top_position[row]; };
          for (Index s = symbolic.first_descendant[root]; s <= root; ++s)
            forward(s, x, local_below, outside, gathered[k].data(), top_size);
        });
      });
      for (Index k = 0; k < n_subtrees; ++k)
        for (Index r = 0; r < n_rhs; ++r)
          for (Index position = 0; position < top_size; ++position)
            x[partition->top_columns[position] + r * symbolic.n] -= gathered[k][position + r * top_size];
      for (const Index s : partition->top_supernodes)
        forward(s, x, below, inside, static_cast<Real *>(nullptr), 0);
      for (auto s = partition->top_supernodes.rbegin(); s != partition->top_supernodes.rend(); ++s)
        backward(*s, x, below);
      arena.execute([&] {
        tbb::parallel_for(Index(0), n_subtrees, [&](const Index k) {
          std::vector<Real> local_below;
          const Index       root = partition->subtree_roots[k];
          for (Index s = root; s >= symbolic.first_descendant[root]; --s)
            backward(s, x, local_below);
        });
      });
    }

    /** solve_by_supernodes() with BLAS on the blocks of L in @p values. */
    template <typename Real>
    void supernodal_solve(const SupernodalSymbolic &symbolic, const Real *values, Real *x, const Index n_rhs,
                          const SolvePartition *partition)
    {
      solve_by_supernodes(
        symbolic, x, n_rhs, partition,
        [&](const Index s, Real *y, std::vector<Real> &below, const auto &outside, Real *gathered,
            const Index gathered_size) {
          forward_supernode(symbolic, values, y, n_rhs, s, below, outside, gathered, gathered_size);
        },
        [&](const Index s, Real *y, std::vector<Real> &below) {
          backward_supernode(symbolic, values, y, n_rhs, s, below);
        });
    }

    /**
     * solve_by_supernodes() for one right-hand side with a column-scaled copy of L
     * (scaled_solve.h): @p stored its blocks, @p scale and @p inverse_diagonal per column.
     */
    template <typename Stored>
    void scaled_solve(const SupernodalSymbolic &symbolic, const Stored *stored, const std::vector<Index> &copy_start,
                      const float *scale, const float *inverse_diagonal, float *x, const SolvePartition *partition)
    {
      // work: x on the supernode's columns, on its rows below, then the last tile's rows past nr.
      solve_by_supernodes(
        symbolic, x, Index(1), partition,
        [&](const Index s, float *y, std::vector<float> &work, const auto &outside, float *gathered,
            const Index) {
          const Index  f = symbolic.first_column[s], nc = symbolic.n_columns(s), nr = symbolic.n_rows(s);
          const Index *rows = symbolic.row_index.data() + symbolic.row_start[s];
          work.resize(std::max<std::size_t>(work.size(), static_cast<std::size_t>(nr + scaled_tile_rows)));
          std::copy(y + f, y + f + nc, work.begin());
          std::fill(work.begin() + nc, work.begin() + nr + scaled_tile_rows, 0.f);
          forward_scaled(stored + copy_start[s], nr, nc, scale + f, inverse_diagonal + f, work.data());
          std::copy(work.begin(), work.begin() + nc, y + f);
          // The rows below hold -L21 y_s: what the rows below (or the top's gathered rows) take.
          for (Index i = 0; i < nr - nc; ++i)
            {
              const Index position = outside(rows[nc + i]);
              if (position < 0)
                y[rows[nc + i]] += work[nc + i];
              else
                gathered[position] -= work[nc + i];
            }
        },
        [&](const Index s, float *y, std::vector<float> &work) {
          const Index  f = symbolic.first_column[s], nc = symbolic.n_columns(s), nr = symbolic.n_rows(s);
          const Index *rows = symbolic.row_index.data() + symbolic.row_start[s];
          work.resize(std::max<std::size_t>(work.size(), static_cast<std::size_t>(nr + scaled_tile_rows)));
          std::copy(y + f, y + f + nc, work.begin());
          for (Index i = 0; i < nr - nc; ++i)
            work[nc + i] = y[rows[nc + i]];
          std::fill(work.begin() + nr, work.begin() + nr + scaled_tile_rows, 0.f);
          backward_scaled(stored + copy_start[s], nr, nc, scale + f, inverse_diagonal + f, work.data());
          std::copy(work.begin(), work.begin() + nc, y + f);
        });
    }
  } // namespace

  struct SupernodalFactor::Implementation
  {
    std::vector<double>                        values;
    /** The preconditioner's copy of values, scaled per column (scaled_solve.h): one of the two, or none. */
    PreconditionerPrecision                    copy = PreconditionerPrecision::full;
    std::vector<float>                         single_values;
    std::vector<Half>                          half_values;
    /** Where each supernode's blocks start in the copy (its own layout, scaled_solve.h). */
    std::vector<Index>                         copy_start;
    /** Per column: the power of two it is scaled by, and 1 / its scaled diagonal entry. */
    std::vector<float>                         column_scale, inverse_diagonal;
    /** Per supernode: the seconds per flop of its computations, averaged; negative if none (timed_seconds()). */
    std::vector<float>                         seconds_per_flop;

    /** Round the columns of supernode s from its local column q on into the copy. */
    void round(const SupernodalSymbolic &symbolic, const Index s, const Index q)
    {
      const Index   f = symbolic.first_column[s], nr = symbolic.n_rows(s), nc = symbolic.n_columns(s);
      const double *block = values.data() + symbolic.value_start[s];
      if (copy == PreconditionerPrecision::single)
        round_columns(block, nr, nc, q, single_values.data() + copy_start[s], column_scale.data() + f,
                      inverse_diagonal.data() + f);
      else if (copy == PreconditionerPrecision::half)
        round_columns(block, nr, nc, q, half_values.data() + copy_start[s], column_scale.data() + f,
                      inverse_diagonal.data() + f);
    }
    /**
     * Per supernode, its first local column whose copy is older than the values (none:
     * clean_copy). The copy is rounded when a preconditioner's solve first reads it, or
     * when round_copy() is asked: a factor that is next solved directly (as after most
     * updates and partial refactorizations) never pays for it.
     */
    static constexpr Index     clean_copy = std::numeric_limits<Index>::max();
    std::vector<Index>         stale_copy_from;
    std::atomic<bool>          copy_stale{false};
    std::mutex                 copy_mutex;

    /** The copy of supernode s is older than the values from its local column q on. */
    void mark_stale(const Index s, const Index q)
    {
      if (copy == PreconditionerPrecision::full)
        return;
      stale_copy_from[s] = std::min(stale_copy_from[s], q);
      copy_stale.store(true, std::memory_order_release);
    }

    /** Round what is stale into the copy; safe beside other threads' calls. */
    void round_stale(const SupernodalSymbolic &symbolic)
    {
      if (!copy_stale.load(std::memory_order_acquire))
        return;
      const std::lock_guard<std::mutex> lock(copy_mutex);
      if (!copy_stale.load(std::memory_order_relaxed))
        return;
      for (Index s = 0; s < static_cast<Index>(stale_copy_from.size()); ++s)
        if (stale_copy_from[s] != clean_copy)
          {
            round(symbolic, s, stale_copy_from[s]);
            stale_copy_from[s] = clean_copy;
          }
      copy_stale.store(false, std::memory_order_release);
    }

    /** The split of the tree for threaded solves, made on first use for that many threads. */
    std::unique_ptr<SolvePartition>            partition;
    unsigned int                               partition_threads = 0;
    std::mutex                                 partition_mutex;

    /** The partition, its arena made for @p n_threads threads. */
    const SolvePartition *partition_for(const SupernodalSymbolic &symbolic, const unsigned int n_threads)
    {
      const std::lock_guard<std::mutex> lock(partition_mutex);
      if (!partition || partition_threads != n_threads)
        {
          partition         = std::make_unique<SolvePartition>(partition_for_solve(symbolic, n_threads));
          partition_threads = n_threads;
        }
      return partition.get();
    }
    tbb::enumerable_thread_specific<Workspace> workspaces;
    /** The buffers of updates and downdates, kept from one to the next. */
    ModificationWorkspace                      modification_workspace;
  };

  SupernodalFactor::SupernodalFactor()
    : implementation(std::make_unique<Implementation>())
  {}

  SupernodalFactor::~SupernodalFactor() = default;

  SupernodalFactor::SupernodalFactor(const SupernodalFactor &other)
    : implementation(std::make_unique<Implementation>())
  {
    *this = other;
  }

  SupernodalFactor::SupernodalFactor(SupernodalFactor &&other) noexcept = default;

  SupernodalFactor &SupernodalFactor::operator=(SupernodalFactor &&other) noexcept = default;

  SupernodalFactor &SupernodalFactor::operator=(const SupernodalFactor &other)
  {
    implementation->values           = other.implementation->values;
    implementation->copy             = other.implementation->copy;
    implementation->single_values    = other.implementation->single_values;
    implementation->half_values      = other.implementation->half_values;
    implementation->copy_start       = other.implementation->copy_start;
    implementation->column_scale     = other.implementation->column_scale;
    implementation->inverse_diagonal = other.implementation->inverse_diagonal;
    implementation->seconds_per_flop = other.implementation->seconds_per_flop;
    implementation->stale_copy_from  = other.implementation->stale_copy_from;
    implementation->copy_stale.store(other.implementation->copy_stale.load());
    return *this;
  }

  void SupernodalFactor::initialize(const SupernodalSymbolic &symbolic, const PreconditionerPrecision copy)
  {
    Implementation &data = *implementation;
    data.partition.reset();
    data.values.assign(symbolic.n_stored_values(), 0.);
    data.copy            = copy;
    data.copy_start.clear();
    if (copy != PreconditionerPrecision::full)
      {
        const Index ns = symbolic.n_supernodes();
        data.copy_start.assign(ns + 1, 0);
        for (Index s = 0; s < ns; ++s)
          data.copy_start[s + 1] = data.copy_start[s] + scaled_copy_entries(symbolic.n_rows(s), symbolic.n_columns(s));
      }
    const Index n_copy = copy == PreconditionerPrecision::full ? 0 : data.copy_start.back();
    const Index n_single = copy == PreconditionerPrecision::single ? n_copy : 0;
    const Index n_half   = copy == PreconditionerPrecision::half ? n_copy : 0;
    const Index n_scales = copy == PreconditionerPrecision::full ? 0 : symbolic.n;
    data.single_values.assign(n_single, 0.f);
    data.half_values.assign(n_half, Half{});
    data.column_scale.assign(n_scales, 1.f);
    data.inverse_diagonal.assign(n_scales, 0.f);
    data.stale_copy_from.assign(symbolic.n_supernodes(), Implementation::clean_copy);
    data.copy_stale = false;
  }

  void SupernodalFactor::clear(const PreconditionerPrecision copy)
  {
    Implementation &data = *implementation;
    data.partition.reset();
    std::vector<double>().swap(data.values);
    std::vector<float>().swap(data.single_values);
    std::vector<Half>().swap(data.half_values);
    std::vector<Index>().swap(data.copy_start);
    std::vector<float>().swap(data.column_scale);
    std::vector<float>().swap(data.inverse_diagonal);
    std::vector<Index>().swap(data.stale_copy_from);
    data.copy_stale = false;
    data.copy       = copy;
  }

  std::size_t SupernodalFactor::memory_bytes() const
  {
    const Implementation &data = *implementation;
    return data.values.capacity() * sizeof(double) + data.single_values.capacity() * sizeof(float) +
           data.half_values.capacity() * sizeof(Half) + data.copy_start.capacity() * sizeof(Index) +
           (data.column_scale.capacity() + data.inverse_diagonal.capacity()) * sizeof(float);
  }

  void SupernodalFactor::save(BinaryWriter &writer) const
  {
    // The copy is rounded again on load: it follows from the values. Where the single
    // copy was once written, the supernodes' timings (an empty list in older files).
    writer.write(implementation->values);
    writer.write(implementation->seconds_per_flop);
  }

  void SupernodalFactor::load(BinaryReader &reader, const SupernodalSymbolic &symbolic)
  {
    Implementation &data = *implementation;
    reader.read(data.values);
    std::vector<float> timings;
    reader.read(timings);
    if (!timings.empty() && static_cast<Index>(timings.size()) != symbolic.n_supernodes())
      reader.fail("the supernodal factor holds " + std::to_string(timings.size()) +
                  " timings, this analysis has " + std::to_string(symbolic.n_supernodes()) + " supernodes");
    data.seconds_per_flop = std::move(timings);
    // None if the writer had not factorized yet.
    const auto n = data.values.empty() ? 0 : static_cast<std::size_t>(symbolic.n_stored_values());
    if (data.values.size() != n)
      reader.fail("the supernodal factor holds " + std::to_string(data.values.size()) + " values, this analysis " +
                  std::to_string(n));
    if (n == 0)
      return;
    std::vector<double> values = std::move(data.values);
    initialize(symbolic, data.copy);
    data.values = std::move(values);
    for (Index s = 0; s < symbolic.n_supernodes(); ++s)
      data.round(symbolic, s, 0);
  }

  void SupernodalFactor::allocate(const SupernodalSymbolic &symbolic)
  {
    if (static_cast<Index>(implementation->values.size()) != symbolic.n_stored_values())
      initialize(symbolic, implementation->copy);
  }

  double SupernodalFactor::factorize(const SupernodalSymbolic &symbolic,
                                     const sparse::CSCMatrix  &lower,
                                     const std::vector<Index> &supernodes,
                                     const std::vector<Index> &start_offsets,
                                     const unsigned int        n_threads)
  {
    allocate(symbolic);
    for (Workspace &workspace : implementation->workspaces)
      workspace.flops = 0;
    if (static_cast<Index>(implementation->seconds_per_flop.size()) != symbolic.n_supernodes())
      implementation->seconds_per_flop.assign(symbolic.n_supernodes(), -1.f);
    NumericRun run(symbolic, lower, implementation->values.data(), implementation->seconds_per_flop.data(),
                   implementation->workspaces, n_threads);
    run.run(supernodes, start_offsets);
    // What was recomputed is to be rounded into the preconditioner's copy (of each
    // supernode, its columns from the offset on), when it is next read.
    if (supernodes.empty())
      for (Index s = 0; s < symbolic.n_supernodes(); ++s)
        implementation->mark_stale(s, 0);
    else
      for (std::size_t k = 0; k < supernodes.size(); ++k)
        implementation->mark_stale(supernodes[k], start_offsets.empty() ? 0 : start_offsets[k]);
    double flops = 0;
    for (const Workspace &workspace : implementation->workspaces)
      flops += workspace.flops;
    return flops;
  }

  double SupernodalFactor::timed_seconds(const SupernodalSymbolic &symbolic, const std::vector<Index> &supernodes,
                                         const std::vector<Index> &start_offsets) const
  {
    const std::vector<float> &rate = implementation->seconds_per_flop;
    if (static_cast<Index>(rate.size()) != symbolic.n_supernodes())
      return -1;
    double seconds = 0;
    for (std::size_t k = 0; k < supernodes.size(); ++k)
      {
        const Index  s     = supernodes[k];
        const double flops = symbolic.flops_from(s, start_offsets.empty() ? 0 : start_offsets[k]);
        if (flops > 0 && !(rate[s] >= 0))
          return -1;
        seconds += flops > 0 ? flops * rate[s] : 0.;
      }
    return seconds;
  }

  ModificationResult SupernodalFactor::modify(const SupernodalSymbolic &symbolic, const sparse::CSCMatrix &c,
                                              const ModificationPlan &plan, const std::vector<double> &signs,
                                              const ModificationSettings &settings)
  {
    if (static_cast<Index>(implementation->values.size()) != symbolic.n_stored_values())
      throw Error("modify() called before factorize()");
    const ModificationResult result = modify_supernodal(symbolic, implementation->values.data(), c, plan, signs,
                                                        settings, implementation->modification_workspace);
    if (implementation->copy != PreconditionerPrecision::full)
      for (std::size_t k = 0; k < plan.supernodes.size(); ++k)
        implementation->mark_stale(plan.supernodes[k], plan.start_columns[k]);
    return result;
  }

  void SupernodalFactor::round_copy(const SupernodalSymbolic &symbolic)
  {
    implementation->round_stale(symbolic);
  }

  void SupernodalFactor::solve(const SupernodalSymbolic &symbolic, double *x, const Index n_rhs,
                               const unsigned int n_threads) const
  {
    supernodal_solve(symbolic, implementation->values.data(), x, n_rhs,
                     implementation->partition_for(symbolic, n_threads));
  }

  void SupernodalFactor::solve_preconditioner(const SupernodalSymbolic &symbolic, double *x,
                                              const unsigned int n_threads) const
  {
    const Implementation &data = *implementation;
    if (data.copy == PreconditionerPrecision::full)
      {
        solve(symbolic, x, 1, n_threads);
        return;
      }
    implementation->round_stale(symbolic);
    std::vector<float> y(symbolic.n, 0.f);
    std::copy(x, x + symbolic.n, y.begin());
    const SolvePartition *partition = implementation->partition_for(symbolic, n_threads);
    if (data.copy == PreconditionerPrecision::single)
      scaled_solve(symbolic, data.single_values.data(), data.copy_start, data.column_scale.data(),
                   data.inverse_diagonal.data(), y.data(), partition);
    else
      scaled_solve(symbolic, data.half_values.data(), data.copy_start, data.column_scale.data(),
                   data.inverse_diagonal.data(), y.data(), partition);
    std::copy(y.begin(), y.begin() + symbolic.n, x);
  }

  sparse::CSCMatrix SupernodalFactor::to_csc(const SupernodalSymbolic &symbolic) const
  {
    sparse::CSCMatrix l = sparse::CSCMatrix::zero(symbolic.n, symbolic.n);
    for (Index s = 0; s < symbolic.n_supernodes(); ++s)
      {
        const Index   nc = symbolic.n_columns(s), nr = symbolic.n_rows(s);
        const double *ls = implementation->values.data() + symbolic.value_start[s];
        for (Index c = 0; c < nc; ++c)
          {
            for (Index r = c; r < nr; ++r)
              {
                l.row_index.push_back(symbolic.row_index[symbolic.row_start[s] + r]);
                l.values.push_back(ls[r + c * nr]);
              }
            l.column_start[symbolic.first_column[s] + c + 1] = static_cast<Index>(l.row_index.size());
          }
      }
    return l;
  }

  const std::vector<double> &SupernodalFactor::values() const
  {
    return implementation->values;
  }
} // namespace warpchol::cholesky
