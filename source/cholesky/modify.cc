#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/cholesky/modify.h>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <type_traits>

#if defined(__SSE2__)
#  include <emmintrin.h>
#endif

#include "modify_kernel.h"
#include "subtree_tasks.h"

namespace warpchol::cholesky
{
  namespace
  {
    /**
     * std::copy with stores that bypass the caches: a downdate's copy of what it changes is
     * read back only if the downdate fails, and held in the caches it would push out the
     * factor's columns that the downdate reads next.
     */
    void copy_past_caches(const double *begin, const double *end, double *target)
    {
#if defined(__SSE2__)
      for (; begin < end && reinterpret_cast<std::uintptr_t>(target) % 16 != 0; ++begin, ++target)
        *target = *begin;
      for (; begin + 2 <= end; begin += 2, target += 2)
        _mm_stream_pd(target, _mm_loadu_pd(begin));
      for (; begin < end; ++begin, ++target)
        *target = *begin;
      _mm_sfence();
#else
      std::copy(begin, end, target);
#endif
    }

    /** Columns of C per pass over the paths: one bit each in a supernode's mask. */
    constexpr Index group_columns = 64;
    /** Supernodes whose own work exceeds this many flops split their rows over threads. */
    constexpr double threaded_supernode_flops = 2e6;

    /** Entries of L in the local columns [q, nc) of supernode s, diagonal included. */
    Index entries_from(const SupernodalSymbolic &symbolic, const Index s, const Index q)
    {
      const Index nc = symbolic.n_columns(s), nr = symbolic.n_rows(s);
      return (nc - q) * nr - (q + nc - 1) * (nc - q) / 2;
    }

    Index n_chunks(const Index rank)
    {
      return (rank + chunk_columns - 1) / chunk_columns;
    }

    /** Flops of a modification of rank @p rank of supernode s from its local column q on. */
    double supernode_modification_flops(const SupernodalSymbolic &symbolic, const Index s, const Index q,
                                        const Index rank)
    {
      return static_cast<double>(entries_from(symbolic, s, q)) *
             (4. * static_cast<double>(rank) + 3. * static_cast<double>(n_chunks(rank)));
    }

    /** Where a change entering supernode @p child goes on in its parent: the local column of its first row below. */
    Index entry_column_in_parent(const SupernodalSymbolic &symbolic, const Index child)
    {
      const Index p = symbolic.supernode_parent[child];
      return symbolic.row_index[symbolic.row_start[child] + symbolic.n_columns(child)] - symbolic.first_column[p];
    }

    /** What one thread needs to modify a supernode. */
    struct Workspace
    {
      /** The supernode's rows of the active columns of W, column by column. */
      std::vector<double> w;
      std::vector<double> reflectors;
      /** The last partial group of rows of L, padded (ChunkKernel::tail). */
      std::vector<double> tail;
      std::vector<double> signs;
      std::vector<Index>  active;
    };
  } // namespace

  struct ModificationWorkspace::Buffers
  {
    /** Per supernode, its position among the paths of the group being modified; -1 between calls. */
    std::vector<Index>                         path_index;
    /** The group's columns of W, row-major, on the paths' columns. */
    std::vector<double>                        w;
    /** A downdate's copy of what it changes (not initialized: only what is kept is read). */
    std::unique_ptr<double[]>                  backup;
    Index                                      backup_capacity = 0;
    std::vector<Index>                         backup_start, backup_first;
    tbb::enumerable_thread_specific<Workspace> workspaces;
  };

  ModificationWorkspace::ModificationWorkspace()
    : data(std::make_unique<Buffers>())
  {}

  ModificationWorkspace::~ModificationWorkspace() = default;

  ModificationWorkspace::ModificationWorkspace(ModificationWorkspace &&) noexcept = default;

  ModificationWorkspace &ModificationWorkspace::operator=(ModificationWorkspace &&) noexcept = default;

  ModificationWorkspace::Buffers &ModificationWorkspace::buffers()
  {
    return *data;
  }

  namespace
  {
    /**
     * One modify_supernodal() call: the columns of C a group of at most 64 at a time, each
     * group one pass over the supernodes on its paths.
     */
    class ModificationRun
    {
    public:
      ModificationRun(const SupernodalSymbolic &symbolic, double *values, const sparse::CSCMatrix &c,
                      const ModificationPlan &plan, const std::vector<double> &signs,
                      const ModificationSettings &settings, ModificationWorkspace::Buffers &buffers)
        : symbolic(symbolic)
        , values(values)
        , c(c)
        , plan(plan)
        , signs(signs)
        , settings(settings)
        , path_index(buffers.path_index)
        , w(buffers.w)
        , backup_start(buffers.backup_start)
        , backup_first(buffers.backup_first)
        , buffers(buffers)
        , workspaces(buffers.workspaces)
      {
        if (static_cast<Index>(path_index.size()) != symbolic.n_supernodes())
          path_index.assign(symbolic.n_supernodes(), -1);
        for (const double sign : signs)
          keeps_backup = keeps_backup || (sign < 0 && settings.restore_on_failure);
      }

      ModificationResult run()
      {
        ModificationResult result;
        if (keeps_backup)
          allocate_backup();
        try
          {
            for (Index first = 0; first < c.n_cols; first += group_columns)
              run_group(first, std::min(c.n_cols, first + group_columns), result);
          }
        catch (...)
          {
            forget_paths();
            restore();
            throw;
          }
        forget_paths();
        return result;
      }

    private:
      const SupernodalSymbolic   &symbolic;
      double                     *values;
      const sparse::CSCMatrix    &c;
      /** plan_modification() of c: the supernodes a downdate's backup keeps. */
      const ModificationPlan     &plan;
      const std::vector<double>  &signs;
      const ModificationSettings &settings;

      /** The supernodes of the group's paths, their position in path, -1 elsewhere. */
      std::vector<Index>         path;
      std::vector<Index>        &path_index;
      /** Per path position: its first row of W, which columns of the group pass through it, where they start. */
      std::vector<Index>         w_row_start;
      std::vector<std::uint64_t> active_mask;
      /** The group's columns of W, row-major (group_size per row), on the path's columns only. */
      std::vector<double>       &w;
      Index                      first_group_column = 0, group_size = 0;
      /** Per column of the group: the row (permuted) of its first entry that may be nonzero. */
      std::vector<Index>         entry_row;

      bool                       keeps_backup = false;
      /**
       * A downdate keeps each supernode's values as they were before it touched them:
       * value v of supernode s at backup[backup_start[s] + v], for v from backup_first[s]
       * on (-1: none kept yet).
       */
      std::vector<Index>                         &backup_start, &backup_first;
      ModificationWorkspace::Buffers             &buffers;
      tbb::enumerable_thread_specific<Workspace> &workspaces;

      /** Leave every path_index at -1 for the next call. */
      void forget_paths()
      {
        for (const Index s : path)
          path_index[s] = -1;
        path.clear();
      }

      Index w_row(const Index row) const
      {
        const Index s = symbolic.supernode_of[row];
        return w_row_start[path_index[s]] + row - symbolic.first_column[s];
      }

      void run_group(const Index begin, const Index end, ModificationResult &result)
      {
        first_group_column = begin;
        group_size         = end - begin;
        // The paths: from each column's first row to the root.
        for (const Index s : path)
          path_index[s] = -1;
        path.clear();
        entry_row.assign(group_size, -1);
        std::vector<std::uint64_t> start_mask;
        for (Index t = begin; t < end; ++t)
          {
            if (c.column_start[t] == c.column_start[t + 1])
              continue;
            const Index first = c.row_index[c.column_start[t]];
            entry_row[t - begin] = first;
            for (Index s = symbolic.supernode_of[first]; s != -1 && path_index[s] == -1; s = symbolic.supernode_parent[s])
              {
                path_index[s] = 0;
                path.push_back(s);
              }
          }
        std::sort(path.begin(), path.end());
        w_row_start.assign(path.size() + 1, 0);
        active_mask.assign(path.size(), 0);
        for (std::size_t k = 0; k < path.size(); ++k)
          {
            path_index[path[k]] = static_cast<Index>(k);
            w_row_start[k + 1]  = w_row_start[k] + symbolic.n_columns(path[k]);
          }
        for (Index t = 0; t < group_size; ++t)
          if (entry_row[t] >= 0)
            active_mask[path_index[symbolic.supernode_of[entry_row[t]]]] |= std::uint64_t(1) << t;
        for (std::size_t k = 0; k < path.size(); ++k)
          {
            const Index p = symbolic.supernode_parent[path[k]];
            if (p != -1)
              active_mask[path_index[p]] |= active_mask[k];
          }
        w.assign(static_cast<std::size_t>(w_row_start.back() * group_size), 0.);
        for (Index t = begin; t < end; ++t)
          for (Index k = c.column_start[t]; k < c.column_start[t + 1]; ++k)
            w[w_row(c.row_index[k]) * group_size + (t - begin)] = c.values[k];

        std::vector<double> flops(path.size(), 0.);
        for_each_supernode_bottom_up(
          symbolic, path, settings.n_threads, [&](const Index s) { return path_index[s] >= 0; },
          [&](const Index s) {
            const Index rank = __builtin_popcountll(active_mask[path_index[s]]);
            return supernode_modification_flops(symbolic, s, 0, rank);
          },
          [&](const Index s, const bool joined) {
            if (joined)
              {
                // Its own buffers: while it waits on its rows' threads, this thread may run
                // other supernodes' tasks with its thread-local workspace.
                Workspace own;
                flops[path_index[s]] = modify_supernode(s, own, true);
              }
            else
              flops[path_index[s]] = modify_supernode(s, workspaces.local(), false);
          });
        for (std::size_t k = 0; k < path.size(); ++k)
          {
            result.flops += flops[k];
            ++result.supernodes;
            result.columns += symbolic.n_columns(path[k]);
          }
      }

      /** Modify supernode s by the group's columns that pass through it; returns the flops. */
      double modify_supernode(const Index s, Workspace &workspace, const bool joined)
      {
        const Index          position = path_index[s];
        const std::uint64_t  mask     = active_mask[position];
        const Index          f = symbolic.first_column[s], nc = symbolic.n_columns(s), nr = symbolic.n_rows(s);
        const Index         *rows = symbolic.row_index.data() + symbolic.row_start[s];
        double              *block = values + symbolic.value_start[s];
        std::vector<Index>  &active = workspace.active;
        active.clear();
        Index q_min = nc;
        for (Index t = 0; t < group_size; ++t)
          if ((mask >> t) & 1)
            {
              active.push_back(t);
              q_min = std::min(q_min, entry_row[t] - f);
            }
        const Index rank = static_cast<Index>(active.size());
        // A downdate keeps what it changes (the columns from q_min on) until it has succeeded;
        // an earlier group may have kept a part of them already.
        if (keeps_backup)
          {
            const Index first = q_min * nr, kept = backup_first[s] < 0 ? nr * nc : backup_first[s];
            if (first < kept)
              {
                copy_past_caches(block + first, block + kept, buffers.backup.get() + backup_start[s] + first);
                backup_first[s] = first;
              }
          }

        // Gather the active columns of W on the rows of s (from q_min: the rows above are 0).
        // Rows above q_min are never read: no need to clear them.
        // A group of rows of padding past the last row: zeros, which stay zero.
        const Index ldw = nr + lanes;
        if (workspace.w.size() < static_cast<std::size_t>(ldw * rank))
          workspace.w.resize(static_cast<std::size_t>(ldw * rank));
        for (Index a = 0; a < rank; ++a)
          std::fill(workspace.w.begin() + a * ldw + nr, workspace.w.begin() + (a + 1) * ldw, 0.);
        if (workspace.tail.size() < static_cast<std::size_t>(nc * lanes))
          workspace.tail.resize(static_cast<std::size_t>(nc * lanes));
        workspace.signs.resize(rank);
        for (Index a = 0; a < rank; ++a)
          workspace.signs[a] = signs[first_group_column + active[a]];
        const Index own_rows = w_row_start[position];
        for (Index i = q_min; i < nr; ++i)
          {
            const double *source = w.data() + (i < nc ? own_rows + i : w_row(rows[i])) * group_size;
            for (Index a = 0; a < rank; ++a)
              workspace.w[a * ldw + i] = source[active[a]];
          }

        // Chunks of at most the target's columns, of balanced sizes, one after the other.
        const Index target_columns = chunk_columns_here();
        const Index chunks         = (rank + target_columns - 1) / target_columns;
        double      flops  = 0;
        // Room for the reflectors with each coefficient a whole vector, and for aligning them.
        workspace.reflectors.resize(static_cast<std::size_t>((nc * (2 * chunk_columns + 2) + 1) * lanes));
        for (Index k = 0, a0 = 0; k < chunks; ++k)
          {
            const Index size = rank / chunks + (k < rank % chunks ? 1 : 0);
            Index       q    = nc;
            for (Index a = a0; a < a0 + size; ++a)
              q = std::min(q, entry_row[active[a]] - f);
            const bool threaded =
              joined && supernode_modification_flops(symbolic, s, q, size) > threaded_supernode_flops;
            SupernodeChunk chunk;
            chunk.l            = block;
            chunk.nr           = nr;
            chunk.nc           = nc;
            chunk.w            = workspace.w.data() + a0 * ldw;
            chunk.ldw          = ldw;
            chunk.sign         = workspace.signs.data() + a0;
            chunk.reflectors   = workspace.reflectors.data();
            chunk.tail         = workspace.tail.data();
            chunk.q            = q;
            chunk.tolerance    = settings.pivot_tolerance;
            chunk.first_column = f;
            chunk.threaded     = threaded;
            run_chunk(size, chunk);
            flops += supernode_modification_flops(symbolic, s, q, size);
            a0 += size;
          }

        // Scatter what goes on to the rows below; the columns now start at s's first row below.
        for (Index i = nc; i < nr; ++i)
          {
            double *target = w.data() + w_row(rows[i]) * group_size;
            for (Index a = 0; a < rank; ++a)
              target[active[a]] = workspace.w[a * ldw + i];
          }
        for (const Index t : active)
          entry_row[t] = nr > nc ? rows[nc] : symbolic.n;
        return flops;
      }

      /**
       * Room for what a downdate may change: of each supernode on the paths of all of C,
       * its values from the first column any group changes (the plan's start) on.
       */
      void allocate_backup()
      {
        backup_start.assign(symbolic.n_supernodes(), -1);
        backup_first.assign(symbolic.n_supernodes(), -1);
        Index total = 0;
        for (std::size_t k = 0; k < plan.supernodes.size(); ++k)
          {
            const Index s = plan.supernodes[k], first = plan.start_columns[k] * symbolic.n_rows(s);
            backup_start[s] = total - first;
            total += symbolic.value_start[s + 1] - symbolic.value_start[s] - first;
          }
        // Not value-initialized: only what is kept is ever read.
        if (buffers.backup_capacity < total)
          {
            buffers.backup.reset(new double[total]);
            buffers.backup_capacity = total;
          }
      }

      /** Put back the values of every supernode a failed downdate touched. */
      void restore()
      {
        if (!keeps_backup)
          return;
        for (Index s = 0; s < symbolic.n_supernodes(); ++s)
          if (backup_first[s] >= 0)
            std::copy(buffers.backup.get() + backup_start[s] + backup_first[s],
                      buffers.backup.get() + backup_start[s] + (symbolic.value_start[s + 1] - symbolic.value_start[s]),
                      values + symbolic.value_start[s] + backup_first[s]);
      }
    };

    /** The plan of columns of C that start at @p first_rows (permuted; -1: an empty column). */
    ModificationPlan plan_from_first_rows(const SupernodalSymbolic &symbolic, const std::vector<Index> &first_rows)
    {
      const Index         ns = symbolic.n_supernodes();
      std::vector<Index>  rank(ns, 0), start(ns, -1);
      std::vector<char>   on_path(ns, 0);
      ModificationPlan    plan;
      const auto          lower_start = [&](const Index s, const Index q) {
        start[s] = start[s] < 0 ? q : std::min(start[s], q);
      };
      for (const Index row : first_rows)
        {
          if (row < 0)
            continue;
          if (row >= symbolic.n)
            throw InputError("a column of the modification starts at row " + std::to_string(row) +
                             ", past the matrix's " + std::to_string(symbolic.n));
          ++plan.rank;
          Index s = symbolic.supernode_of[row];
          ++rank[s];
          lower_start(s, row - symbolic.first_column[s]);
          for (; s != -1 && !on_path[s]; s = symbolic.supernode_parent[s])
            {
              on_path[s] = 1;
              plan.supernodes.push_back(s);
            }
        }
      std::sort(plan.supernodes.begin(), plan.supernodes.end());
      for (const Index s : plan.supernodes)
        {
          const Index p = symbolic.supernode_parent[s];
          if (p != -1)
            {
              rank[p] += rank[s];
              lower_start(p, entry_column_in_parent(symbolic, s));
            }
          plan.start_columns.push_back(start[s]);
          plan.ranks.push_back(rank[s]);
          // Columns of C pass through in groups of 64: a rank past that is several passes.
          const double flops = supernode_modification_flops(symbolic, s, start[s], rank[s]);
          plan.supernode_flops.push_back(flops);
          plan.flops += flops;
          plan.n_columns += symbolic.n_columns(s) - start[s];
          plan.n_entries += entries_from(symbolic, s, start[s]);
        }
      return plan;
    }
  } // namespace

  ModificationPlan plan_modification(const SupernodalSymbolic &symbolic, const sparse::CSCMatrix &c)
  {
    std::vector<Index> first_rows(c.n_cols, -1);
    for (Index t = 0; t < c.n_cols; ++t)
      if (c.column_start[t] < c.column_start[t + 1])
        first_rows[t] = c.row_index[c.column_start[t]];
    return plan_from_first_rows(symbolic, first_rows);
  }

  ModificationPlan plan_modification(const SupernodalSymbolic &symbolic, const std::vector<Index> &first_rows)
  {
    return plan_from_first_rows(symbolic, first_rows);
  }

  void check_modification_pattern(const SupernodalSymbolic &symbolic, const sparse::CSCMatrix &c,
                                  const std::vector<Index> &row_names)
  {
    const auto name = [&](const Index row) { return std::to_string(row_names.empty() ? row : row_names[row]); };
    if (c.n_rows != symbolic.n)
      throw InputError("the modification has " + std::to_string(c.n_rows) + " rows, the factor " +
                       std::to_string(symbolic.n));
    for (Index t = 0; t < c.n_cols; ++t)
      {
        const Index begin = c.column_start[t], end = c.column_start[t + 1];
        for (Index k = begin; k < end; ++k)
          {
            if (c.row_index[k] < 0 || c.row_index[k] >= symbolic.n)
              throw InputError("column " + std::to_string(t) + " of the modification has a row " +
                               std::to_string(c.row_index[k]) + " out of range [0, " + std::to_string(symbolic.n) + ")");
            if (k > begin && c.row_index[k] <= c.row_index[k - 1])
              throw InputError("the rows of column " + std::to_string(t) +
                               " of the modification are not sorted and distinct");
          }
        if (end - begin < 2)
          continue;
        const Index  first = c.row_index[begin], s = symbolic.supernode_of[first];
        const Index *below = symbolic.row_index.data() + symbolic.row_start[s] + symbolic.n_columns(s);
        const Index *last  = symbolic.row_index.data() + symbolic.row_start[s + 1];
        for (Index k = begin + 1; k < end; ++k)
          {
            const Index row = c.row_index[k];
            if (row < symbolic.first_column[s + 1] || std::binary_search(below, last, row))
              continue;
            throw InputError("column " + std::to_string(t) + " of the modification has entries in rows " + name(first) +
                             " and " + name(row) + ", which the factor's structure does not couple: C C^T would fill L " +
                             "outside its analyzed pattern");
          }
      }
  }

  ModificationResult modify_supernodal(const SupernodalSymbolic &symbolic, double *values, const sparse::CSCMatrix &c,
                                       const ModificationPlan &plan, const std::vector<double> &signs,
                                       const ModificationSettings &settings, ModificationWorkspace &workspace)
  {
    if (static_cast<Index>(signs.size()) != c.n_cols)
      throw InputError("the modification has " + std::to_string(c.n_cols) + " columns but " +
                       std::to_string(signs.size()) + " signs");
    for (const double sign : signs)
      if (sign != 1. && sign != -1.)
        throw InputError("a modification's signs are +1 (update) or -1 (downdate), not " + format_number(sign));
    ModificationRun run(symbolic, values, c, plan, signs, settings, workspace.buffers());
    return run.run();
  }
} // namespace warpchol::cholesky
