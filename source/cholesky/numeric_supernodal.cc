#include <warpchol/base/exceptions.h>
#include <warpchol/cholesky/blas.h>
#include <warpchol/cholesky/numeric_supernodal.h>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>

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
                 tbb::enumerable_thread_specific<Workspace> &workspaces,
                 const unsigned int                        n_threads)
        : symbolic(symbolic)
        , lower(lower)
        , values(values)
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
              factor_supernode(s, start_offset[s], workspace);
            return;
          }
        tbb::task_arena arena(static_cast<int>(n_threads));
        arena.execute([&] { run_in_parallel(); });
      }

    private:
      const SupernodalSymbolic                  &symbolic;
      const sparse::CSCMatrix                   &lower;
      double                                    *values;
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
              factor_supernode(*t, start_offset[*t], workspace);
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
        if (symbolic.supernode_flops[s] > parallel_supernode_flops)
          factor_supernode_threaded(s, start_offset[s], workspace);
        else
          factor_supernode(s, start_offset[s], workspace);
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

  struct SupernodalFactor::Implementation
  {
    std::vector<double>                        values;
    /** The single-precision copy of values (empty if none is kept). */
    std::vector<float>                         single_values;
    bool                                       keep_single = false;
    tbb::enumerable_thread_specific<Workspace> workspaces;
  };

  namespace
  {
    /**
     * Overwrite @p x (n x n_rhs, column-major) with the solution of L L^T z = x, the blocks
     * of L in @p values: dtrsm on the diagonal block of each supernode, dgemm for the rows
     * below it, all right-hand sides at once, gathered into / scattered from a dense block.
     */
    template <typename Real>
    void supernodal_solve(const SupernodalSymbolic &symbolic, const Real *values, Real *x, const Index n_rhs)
    {
      const int         n  = static_cast<int>(symbolic.n);
      const int         m  = static_cast<int>(n_rhs);
      const Index       ns = symbolic.n_supernodes();
      std::vector<Real> below(symbolic.n * n_rhs);
      // L y = b: the diagonal block, then the rows below it.
      for (Index s = 0; s < ns; ++s)
        {
          const Index  f = symbolic.first_column[s], nc = symbolic.n_columns(s), nr = symbolic.n_rows(s);
          const int    rows_below = static_cast<int>(nr - nc);
          const Real  *ls         = values + symbolic.value_start[s];
          const Index *rows       = symbolic.row_index.data() + symbolic.row_start[s];
          blas::trsm_left_lower(false, static_cast<int>(nc), m, ls, static_cast<int>(nr), x + f, n);
          if (rows_below == 0)
            continue;
          blas::gemm(false, false, rows_below, m, static_cast<int>(nc), Real(1), ls + nc, static_cast<int>(nr),
                     x + f, n, Real(0), below.data(), rows_below);
          for (Index r = 0; r < n_rhs; ++r)
            for (Index i = 0; i < rows_below; ++i)
              x[rows[nc + i] + r * n] -= below[i + r * rows_below];
        }
      // L^T x = y, supernodes in reverse.
      for (Index s = ns - 1; s >= 0; --s)
        {
          const Index  f = symbolic.first_column[s], nc = symbolic.n_columns(s), nr = symbolic.n_rows(s);
          const int    rows_below = static_cast<int>(nr - nc);
          const Real  *ls         = values + symbolic.value_start[s];
          const Index *rows       = symbolic.row_index.data() + symbolic.row_start[s];
          if (rows_below > 0)
            {
              for (Index r = 0; r < n_rhs; ++r)
                for (Index i = 0; i < rows_below; ++i)
                  below[i + r * rows_below] = x[rows[nc + i] + r * n];
              blas::gemm(true, false, static_cast<int>(nc), m, rows_below, Real(-1), ls + nc,
                         static_cast<int>(nr), below.data(), rows_below, Real(1), x + f, n);
            }
          blas::trsm_left_lower(true, static_cast<int>(nc), m, ls, static_cast<int>(nr), x + f, n);
        }
    }
  } // namespace

  SupernodalFactor::SupernodalFactor()
    : implementation(std::make_unique<Implementation>())
  {}

  SupernodalFactor::~SupernodalFactor() = default;

  SupernodalFactor::SupernodalFactor(const SupernodalFactor &other)
    : implementation(std::make_unique<Implementation>())
  {
    *this = other;
  }

  SupernodalFactor &SupernodalFactor::operator=(const SupernodalFactor &other)
  {
    implementation->values        = other.implementation->values;
    implementation->single_values = other.implementation->single_values;
    implementation->keep_single   = other.implementation->keep_single;
    return *this;
  }

  void SupernodalFactor::initialize(const SupernodalSymbolic &symbolic, const bool single_precision_copy)
  {
    implementation->values.assign(symbolic.n_stored_values(), 0.);
    implementation->keep_single = single_precision_copy;
    implementation->single_values.assign(single_precision_copy ? symbolic.n_stored_values() : 0, 0.f);
  }

  double SupernodalFactor::factorize(const SupernodalSymbolic &symbolic,
                                     const sparse::CSCMatrix  &lower,
                                     const std::vector<Index> &supernodes,
                                     const std::vector<Index> &start_offsets,
                                     const unsigned int        n_threads)
  {
    if (static_cast<Index>(implementation->values.size()) != symbolic.n_stored_values())
      initialize(symbolic, implementation->keep_single);
    for (Workspace &workspace : implementation->workspaces)
      workspace.flops = 0;
    NumericRun run(symbolic, lower, implementation->values.data(), implementation->workspaces, n_threads);
    run.run(supernodes, start_offsets);
    if (implementation->keep_single)
      {
        // Round what was recomputed (of each supernode, its columns from the offset on).
        const auto round = [&](const Index s, const Index q) {
          const Index begin = symbolic.value_start[s] + q * symbolic.n_rows(s), end = symbolic.value_start[s + 1];
          std::copy(implementation->values.begin() + begin, implementation->values.begin() + end,
                    implementation->single_values.begin() + begin);
        };
        if (supernodes.empty())
          for (Index s = 0; s < symbolic.n_supernodes(); ++s)
            round(s, 0);
        else
          for (std::size_t k = 0; k < supernodes.size(); ++k)
            round(supernodes[k], start_offsets.empty() ? 0 : start_offsets[k]);
      }
    double flops = 0;
    for (const Workspace &workspace : implementation->workspaces)
      flops += workspace.flops;
    return flops;
  }

  void SupernodalFactor::solve(const SupernodalSymbolic &symbolic, double *x, const Index n_rhs) const
  {
    supernodal_solve(symbolic, implementation->values.data(), x, n_rhs);
  }

  void SupernodalFactor::solve_single_precision(const SupernodalSymbolic &symbolic, double *x,
                                                const Index n_rhs) const
  {
    if (!implementation->keep_single)
      throw Error("solve_single_precision(): no single-precision copy of the factor is kept");
    std::vector<float> y(x, x + symbolic.n * n_rhs);
    supernodal_solve(symbolic, implementation->single_values.data(), y.data(), n_rhs);
    std::copy(y.begin(), y.end(), x);
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
