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

#include "subtree_tasks.h"

#include <warpchol/base/simd.h>

// What every target shares, compiled once (this file is included again per SIMD target).
#ifndef warpchol_cholesky_modify_shared
#define warpchol_cholesky_modify_shared
namespace warpchol::cholesky
{
  namespace
  {
    /** Columns of C per pass over the paths: one bit each in a supernode's mask. */
    constexpr Index group_columns = 64;
    /**
     * The most columns of C a supernode's reflectors carry in registers at a time on any
     * target (each target carries as many as its registers hold: chunk_columns_here()).
     */
    constexpr Index chunk_columns = 16;
    /** The most rows a reflector is applied to at a time on any target (one vector of doubles). */
    constexpr Index lanes = 8;
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
    /**
     * Applies the reflectors of one chunk of @p n_columns (1 to chunk_columns) columns of C
     * to a supernode (ChunkKernel), on the SIMD target chosen at run time.
     */
    void run_chunk(Index n_columns, double *l, Index nr, Index nc, double *w, Index ldw, const double *sign,
                   double *reflectors, double *tail, Index q, double tolerance, Index first_column, bool threaded);

    /** The most columns of C the target chosen at run time carries in its registers at once. */
    Index chunk_columns_here();

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
                      const std::vector<double> &signs, const ModificationSettings &settings,
                      ModificationWorkspace::Buffers &buffers)
        : symbolic(symbolic)
        , values(values)
        , c(c)
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
                std::copy(block + first, block + kept, buffers.backup.get() + backup_start[s] + first);
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
            run_chunk(size, block, nr, nc, workspace.w.data() + a0 * ldw, ldw, workspace.signs.data() + a0,
                      workspace.reflectors.data(), workspace.tail.data(), q, settings.pivot_tolerance, f, threaded);
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
        const ModificationPlan plan  = plan_modification(symbolic, c);
        Index                  total = 0;
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
                                       const std::vector<double> &signs, const ModificationSettings &settings,
                                       ModificationWorkspace &workspace)
  {
    if (static_cast<Index>(signs.size()) != c.n_cols)
      throw InputError("the modification has " + std::to_string(c.n_cols) + " columns but " +
                       std::to_string(signs.size()) + " signs");
    for (const double sign : signs)
      if (sign != 1. && sign != -1.)
        throw InputError("a modification's signs are +1 (update) or -1 (downdate), not " + format_number(sign));
    ModificationRun run(symbolic, values, c, signs, settings, workspace.buffers());
    return run.run();
  }
} // namespace warpchol::cholesky
#endif

// The kernel that applies the reflectors, once per SIMD target (Highway).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "cholesky/modify.cc"
#include <hwy/foreach_target.h>
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace warpchol::cholesky::HWY_NAMESPACE
{
  namespace
  {
    /**
     * Doubles in one vector register of this target (two on the baseline, which emulates
     * 128 bits). Vectors no wider than a register: a wider one is split into registers the
     * register file cannot hold beside the carried columns, and spilled.
     */
    constexpr Index target_lanes = HWY_MAX_BYTES / sizeof(double) < 2 ? 2 : HWY_MAX_BYTES / sizeof(double);
    static_assert(target_lanes <= lanes, "W's padding and the tail hold at most `lanes` rows");

    /** Vector registers of this target: 16 on x86-64, 32 with AVX-512. */
    constexpr int vector_registers = HWY_MAX_BYTES >= 64 ? 32 : 16;

    /**
     * Columns of W carried in registers at a time: the registers but four (a group's row
     * of L, its sum and the dot product's second sum, and one for the compiler).
     */
    constexpr Index target_chunk_columns = std::min<Index>(chunk_columns, vector_registers - 4);

    using Lanes = double __attribute__((vector_size(sizeof(double) * target_lanes)));

    /** How many columns ahead of the one being modified a group's rows are prefetched. */
    constexpr Index prefetch_columns = 12;

    /**
     * How a reflector's coefficients are kept. AVX-512 multiplies by a double read from
     * memory and broadcast by the instruction itself; the other targets would broadcast
     * each into a register of its own, 2K + 1 of them beside the carried columns, so there
     * each coefficient is kept as a whole vector (the same value in every lane), which a
     * fused multiply-add reads from memory.
     */
    constexpr bool whole_vector_coefficients = vector_registers < 32;
    using Coefficient                        = std::conditional_t<whole_vector_coefficients, Lanes, double>;

    /** The double of a coefficient. */
    template <typename Kept = Coefficient>
    double scalar_of(const Kept &coefficient)
    {
      if constexpr (std::is_same_v<Kept, double>)
        return coefficient;
      else
        return coefficient[0];
    }

    /** A coefficient of value @p value. */
    template <typename Kept = Coefficient>
    Kept as_coefficient(const double value)
    {
      if constexpr (std::is_same_v<Kept, double>)
        return value;
      else
        {
          Kept splatted;
          for (Index k = 0; k < target_lanes; ++k)
            splatted[k] = value;
          return splatted;
        }
    }

    Lanes load(const double *p)
    {
      Lanes v;
      std::memcpy(&v, p, sizeof v);
      return v;
    }

    void store(double *p, const Lanes &v)
    {
      std::memcpy(p, &v, sizeof v);
    }

    /** Lane k holds k: which rows of a group a reflector may change. */
    Lanes lane_numbers()
    {
      Lanes numbers = {};
      for (Index k = 0; k < target_lanes; ++k)
        numbers[k] = static_cast<double>(k);
      return numbers;
    }

    /**
     * The reflectors of one chunk of K columns of C on one supernode, and how they are
     * applied: per local column j, tau_j, v_j (K values) and S v_j (K values).
     *
     * Rows go a vector at a time (a group: target_lanes rows, one register per column of L
     * and of W), from the supernode's first changing column q on. A group that meets the
     * diagonal block first takes the reflectors of the columns before it, then makes its
     * own from its rows one by one, each applied at once to the group's rows below it (the
     * others masked); the groups below the diagonal block take every reflector, a few side
     * by side; the rows past the last whole group go through a copy padded with zeros to a
     * group. Every row is computed by the same operations in the same order, whatever its
     * place, group or target: the same bits for any split of the rows, and on every target
     * with fused multiply-adds.
     */
    template <int K>
    struct ChunkKernel
    {
      /**
       * Coefficients per reflector j: tau, v (K), S v (K), and its coupling with the
       * reflector before it, v_{j-1} . S v_j (the look-ahead of apply_to_groups()).
       */
      static constexpr Index stride = 2 * K + 2;

      double       *l;
      Index         nr, nc;
      /** The supernode's rows of W (ldw >= nr + lanes: zero rows pad the last group). */
      double       *w;
      Index         ldw;
      const double *sign;
      /** stride coefficients per local column, aligned to a vector. */
      Coefficient  *reflectors;
      /** Room for the last, partial group of rows: nc x lanes values. */
      double       *tail;

      /**
       * Row groups carried side by side: each reflector is a chain of dependent operations
       * per group (the new entry, the sum that updates w, the next dot product), and
       * independent groups fill the gaps of one another's chains. As many as the registers
       * hold, each group with its K columns of W, its next row of L and next dot product,
       * two registers left for the sums, and at most eight.
       */
      static constexpr int groups = std::clamp((vector_registers - 2) / (K + 2), 1, 8);

      /** s = l + w . S v for one reflector, in two interleaved sums (the same order everywhere). */
      template <typename Value>
      static Value dot(const Value &old, const Value *carried, const Coefficient *scaled)
      {
        Value even = old;
        if constexpr (K == 1)
          return even + carried[0] * scaled[0];
        else
          {
            Value odd = carried[1] * scaled[1];
            even += carried[0] * scaled[0];
            for (int t = 2; t + 1 < K; t += 2)
              {
                even += carried[t] * scaled[t];
                odd += carried[t + 1] * scaled[t + 1];
              }
            if constexpr (K % 2 == 1)
              even += carried[K - 1] * scaled[K - 1];
            return even + odd;
          }
      }

      /**
       * Apply the reflectors [j_begin, j_end) to G groups of rows: those of L at
       * @p rows (column stride @p ld), those of W from row @p w_row on.
       *
       * Each reflector's dot product is formed before the reflector ahead of it is applied
       * (a look-ahead): with w the carried columns before reflector j,
       *   s_{j+1} = l_{j+1} + w . S v_{j+1} - (l_j + l_j') (v_j . S v_{j+1}),
       * which equals l_{j+1} + w' . S v_{j+1} with w' = w - (l_j + l_j') v_j. The first part
       * depends on w, not on reflector j's result, so it overlaps the chain of reflector j:
       * what remains between two reflectors is two operations, not the whole dot product.
       */
      template <int G>
      void apply_to_groups(double *rows, const Index ld, const Index w_row, const Index j_begin,
                           const Index j_end) const
      {
        if (j_begin >= j_end)
          return;
        Lanes carried[G][K];
        for (int g = 0; g < G; ++g)
          for (int t = 0; t < K; ++t)
            carried[g][t] = load(w + t * ldw + w_row + g * target_lanes);
        Lanes next_old[G], next_dot[G];
        for (int g = 0; g < G; ++g)
          {
            next_old[g] = load(rows + j_begin * ld + g * target_lanes);
            next_dot[g] = dot(next_old[g], carried[g], reflectors + j_begin * stride + 1 + K);
          }
        for (Index j = j_begin; j < j_end; ++j)
          {
            // The group's entries some columns ahead: the columns of a large supernode lie
            // pages apart, where the hardware's prefetchers do not follow.
            if (j + prefetch_columns < j_end)
              {
                const double *ahead = rows + (j + prefetch_columns) * ld;
                for (Index k = 0; k < G * target_lanes; k += 8)
                  __builtin_prefetch(ahead + k, 1);
                __builtin_prefetch(ahead + G * target_lanes - 1, 1);
              }
            const Coefficient *r = reflectors + j * stride;
            Lanes              sum[G];
            for (int g = 0; g < G; ++g)
              {
                const Lanes old     = next_old[g];
                const Lanes changed = r[0] * next_dot[g] - old;
                store(rows + j * ld + g * target_lanes, changed);
                sum[g] = old + changed;
              }
            if (j + 1 < j_end)
              {
                const Coefficient *next = r + stride;
                for (int g = 0; g < G; ++g)
                  {
                    next_old[g] = load(rows + (j + 1) * ld + g * target_lanes);
                    next_dot[g] = dot(next_old[g], carried[g], next + 1 + K) - sum[g] * next[2 * K + 1];
                  }
              }
            for (int g = 0; g < G; ++g)
              for (int t = 0; t < K; ++t)
                carried[g][t] -= sum[g] * r[1 + t];
          }
        for (int g = 0; g < G; ++g)
          for (int t = 0; t < K; ++t)
            store(w + t * ldw + w_row + g * target_lanes, carried[g][t]);
      }

      /**
       * Rows of a block of apply_to_block(): its columns of W (K x block_rows doubles) stay
       * in the first-level cache while every reflector passes over them.
       */
      static constexpr Index block_rows = 16 * target_lanes;

      /**
       * Apply the reflectors [j_begin, j_end) to the @p n_groups groups of rows from row
       * @p w_row (those of L at @p rows, column stride @p ld), W kept in memory instead of
       * registers (targets with 16 registers).
       *
       * apply_to_groups() carries a group's K columns of W in registers: on 16 registers
       * that leaves one group, whose chain of dependent operations from one reflector to
       * the next is longer than the reflector's work. Here reflector by reflector goes over
       * all groups of the block, two at a time (each coefficient read once for both), so
       * that the groups' independent chains overlap; the next reflector's dot product is
       * formed from the columns just modified, as they are stored. The block's columns of W
       * are copied to a buffer of fixed stride, so that every address is a constant offset.
       */
      void apply_to_block(double *rows, const Index ld, const Index w_row, const Index n_groups, const Index j_begin,
                          const Index j_end) const
      {
        constexpr Index    most_groups = block_rows / target_lanes;
        alignas(64) double stored[K * block_rows];
        Lanes              dots[most_groups];
        double *const      w_block = w + w_row;
        const Index        n_rows = n_groups * target_lanes, w_stride = ldw;
        const Coefficient *coefficients = reflectors;
        for (int t = 0; t < K; ++t)
          std::copy(w_block + t * w_stride, w_block + t * w_stride + n_rows, stored + t * block_rows);
        for (Index g = 0; g < n_groups; ++g)
          {
            Lanes carried[K];
            for (int t = 0; t < K; ++t)
              carried[t] = load(stored + t * block_rows + g * target_lanes);
            dots[g] = dot(load(rows + j_begin * ld + g * target_lanes), carried, coefficients + j_begin * stride + 1 + K);
          }
        for (Index j = j_begin; j < j_end; ++j)
          {
            if (j + prefetch_columns < j_end)
              {
                const double *ahead = rows + (j + prefetch_columns) * ld;
                for (Index k = 0; k < n_rows; k += 8)
                  __builtin_prefetch(ahead + k, 1);
                __builtin_prefetch(ahead + n_rows - 1, 1);
              }
            const Coefficient *r      = coefficients + j * stride;
            const Coefficient *next   = j + 1 < j_end ? r + stride : nullptr;
            double            *column = rows + j * ld;
            Index              g      = 0;
            for (; g + 2 <= n_groups; g += 2)
              apply_to_stored_groups<2>(column + g * target_lanes, ld, stored + g * target_lanes, dots + g, r, next);
            if (g < n_groups)
              apply_to_stored_groups<1>(column + g * target_lanes, ld, stored + g * target_lanes, dots + g, r, next);
          }
        for (int t = 0; t < K; ++t)
          std::copy(stored + t * block_rows, stored + t * block_rows + n_rows, w_block + t * w_stride);
      }

      /**
       * Reflector @p r on P groups side by side (their entries of its column at @p column,
       * of W at @p w_rows with stride block_rows, their dot products for it in @p dots);
       * then, if @p next, their dot products for the next reflector, in the order of dot().
       */
      template <int P>
      static void apply_to_stored_groups(double *column, const Index ld, double *w_rows, Lanes *dots,
                                         const Coefficient *r, const Coefficient *next)
      {
        Lanes sum[P];
        for (int p = 0; p < P; ++p)
          {
            const Lanes old     = load(column + p * target_lanes);
            const Lanes changed = r[0] * dots[p] - old;
            store(column + p * target_lanes, changed);
            sum[p] = old + changed;
          }
        if (!next)
          {
#pragma GCC unroll 16
            for (int t = 0; t < K; ++t)
              {
                const Coefficient v = r[1 + t];
                for (int p = 0; p < P; ++p)
                  {
                    double *entry = w_rows + t * block_rows + p * target_lanes;
                    store(entry, load(entry) - sum[p] * v);
                  }
              }
            return;
          }
        Lanes even[P], odd[P];
        for (int p = 0; p < P; ++p)
          even[p] = load(column + ld + p * target_lanes);
#pragma GCC unroll 16
        for (int t = 0; t < K; ++t)
          {
            const Coefficient v = r[1 + t], scaled = next[1 + K + t];
            for (int p = 0; p < P; ++p)
              {
                double     *entry = w_rows + t * block_rows + p * target_lanes;
                const Lanes moved = load(entry) - sum[p] * v;
                store(entry, moved);
                if (t % 2 == 0 || K == 1)
                  even[p] += moved * scaled;
                else if (t == 1)
                  odd[p] = moved * scaled;
                else
                  odd[p] += moved * scaled;
              }
          }
        for (int p = 0; p < P; ++p)
          dots[p] = K == 1 ? even[p] : even[p] + odd[p];
      }

      /** Apply the reflectors [j_begin, j_end) to the whole groups of rows [row_begin, row_end) in place. */
      void apply_to_rows(const Index row_begin, const Index row_end, const Index j_begin, const Index j_end) const
      {
        if (j_begin >= j_end)
          return;
        Index i = row_begin;
        if constexpr (whole_vector_coefficients)
          {
            for (; i + target_lanes <= row_end; i += block_rows)
              {
                apply_to_block(l + i, nr, i, std::min(block_rows, row_end - i) / target_lanes, j_begin, j_end);
              }
            return;
          }
        if constexpr (groups > 1)
          for (; i + groups * target_lanes <= row_end; i += groups * target_lanes)
            apply_to_groups<groups>(l + i, nr, i, j_begin, j_end);
        for (; i + target_lanes <= row_end; i += target_lanes)
          apply_to_groups<1>(l + i, nr, i, j_begin, j_end);
      }

      /**
       * The reflector of column j from its row (L_jj = @p alpha, w_j = @p row_w):
       * (L_jj, w_j) -> (r, 0); returns r. Throws NotPositiveDefinite (column
       * @p first_column + j) if r^2 falls to the tolerance.
       */
      double make_reflector(const Index j, const Index q, const double alpha, const double *row_w,
                            const double tolerance, const Index first_column) const
      {
        double r2 = alpha * alpha, held = alpha * alpha;
        for (int t = 0; t < K; ++t)
          {
            r2 += sign[t] * row_w[t] * row_w[t];
            if (sign[t] > 0)
              held += row_w[t] * row_w[t];
          }
        if (!(r2 > tolerance * held) || !std::isfinite(r2))
          throw NotPositiveDefinite(first_column + j, r2);
        const double r = std::sqrt(r2), denominator = alpha + r;
        Coefficient *reflector = reflectors + j * stride;
        reflector[0]           = as_coefficient(1. + alpha / r);
        double       coupling  = 0;
        for (int t = 0; t < K; ++t)
          {
            const double v       = row_w[t] / denominator;
            reflector[1 + t]     = as_coefficient(v);
            reflector[1 + K + t] = as_coefficient(sign[t] * v);
            if (j > q)
              coupling += scalar_of(reflector[1 + t - stride]) * (sign[t] * v);
          }
        reflector[2 * K + 1] = as_coefficient(coupling);
        return r;
      }

      /**
       * A group of rows that meets the diagonal block (rows from @p i0, those of L at
       * @p rows with column stride @p ld), whose rows took the reflectors before @p from:
       * the reflectors [from, i0), then those of its own rows, each made from its row and
       * applied to the rows below it in the group. The chunk starts at column @p q.
       */
      void diagonal_group(double *rows, const Index ld, const Index i0, const Index from, const Index q,
                          const double tolerance, const Index first_column) const
      {
        apply_to_groups<1>(rows, ld, i0, from, std::min(i0, nc));
        const Lanes numbers = lane_numbers();
        Lanes       carried[K];
        for (int t = 0; t < K; ++t)
          carried[t] = load(w + t * ldw + i0);
        for (Index j = i0; j < std::min(i0 + target_lanes, nc); ++j)
          {
            const int lane = static_cast<int>(j - i0);
            double    row_w[K];
            for (int t = 0; t < K; ++t)
              row_w[t] = carried[t][lane];
            double       *column    = rows + j * ld;
            const Lanes   old       = load(column);
            const double  r         = make_reflector(j, q, old[lane], row_w, tolerance, first_column);
            const Coefficient *reflector = reflectors + j * stride;
            Lanes              changed   = reflector[0] * dot(old, carried, reflector + 1 + K) - old;
            const Lanes   sum       = old + changed;
            // Rows above j keep their values; row j becomes (r, 0) exactly; those below move.
            const auto below = numbers > static_cast<double>(lane);
            changed          = below ? changed : old;
            changed[lane]    = r;
            store(column, changed);
            for (int t = 0; t < K; ++t)
              {
                const Lanes moved = carried[t] - sum * reflector[1 + t];
                carried[t]        = below ? moved : carried[t];
                carried[t][lane]  = 0.;
              }
          }
        for (int t = 0; t < K; ++t)
          store(w + t * ldw + i0, carried[t]);
      }

      /**
       * Modify the supernode from its local column q on, the rows below the diagonal
       * block split over threads if @p threaded.
       */
      void run(const Index q, const double tolerance, const Index first_column, const bool threaded) const
      {
        const Index     whole_end    = q + (nr - q) / target_lanes * target_lanes;
        constexpr Index side_by_side = groups * target_lanes;
        // The diagonal block's rows a panel at a time: the reflectors of the columns before
        // the panel with groups side by side, then group by group those of the panel's
        // columns (one group at a time: each group's rows make the next reflectors).
        constexpr Index panel_rows = 4 * side_by_side;
        Index           i0         = q;
        while (i0 < nc && i0 < whole_end)
          {
            const Index panel_end = std::min(i0 + panel_rows, whole_end);
            apply_to_rows(i0, panel_end, q, i0);
            for (const Index panel = i0; i0 < panel_end; i0 += target_lanes)
              diagonal_group(l + i0, nr, i0, panel, q, tolerance, first_column);
          }
        const Index rows_below = whole_end - i0;
        if (threaded && rows_below > 4 * side_by_side)
          {
            // Each row is computed alone, the same way whatever the split: the same bits
            // for any number of threads.
            const Index block =
              std::max<Index>(2 * side_by_side, (rows_below / (8 * side_by_side) + 1) * side_by_side);
            tbb::parallel_for(Index(0), (rows_below + block - 1) / block, [&](const Index b) {
              apply_to_rows(i0 + b * block, std::min(whole_end, i0 + (b + 1) * block), q, nc);
            });
          }
        else if (rows_below > 0)
          apply_to_rows(i0, whole_end, q, nc);
        if (whole_end == nr)
          return;
        // The last rows, fewer than a group: through a copy padded with zero rows (which
        // stay zero), its columns from q on.
        const Index n_rows = nr - whole_end;
        for (Index j = q; j < nc; ++j)
          for (Index k = 0; k < target_lanes; ++k)
            tail[j * target_lanes + k] = k < n_rows ? l[j * nr + whole_end + k] : 0.;
        diagonal_group(tail, target_lanes, whole_end, q, q, tolerance, first_column);
        for (Index j = q; j < nc; ++j)
          for (Index k = 0; k < n_rows; ++k)
            l[j * nr + whole_end + k] = tail[j * target_lanes + k];
      }
    };

    /** ChunkKernel<K>::run for the K of @p n_columns (1 to target_chunk_columns). */
    template <int K>
    void run_chunk(const Index n_columns, double *l, const Index nr, const Index nc, double *w, const Index ldw,
                   const double *sign, double *reflectors, double *tail, const Index q, const double tolerance,
                   const Index first_column, const bool threaded)
    {
      if constexpr (K < target_chunk_columns)
        if (n_columns > K)
          {
            run_chunk<K + 1>(n_columns, l, nr, nc, w, ldw, sign, reflectors, tail, q, tolerance, first_column,
                             threaded);
            return;
          }
      // The reflectors' room aligned to a vector (it has a vector of doubles to spare).
      constexpr std::uintptr_t alignment = alignof(Coefficient);
      const auto               aligned   = reinterpret_cast<Coefficient *>(
        (reinterpret_cast<std::uintptr_t>(reflectors) + alignment - 1) / alignment * alignment);
      const ChunkKernel<K> kernel{l, nr, nc, w, ldw, sign, aligned, tail};
      kernel.run(q, tolerance, first_column, threaded);
    }

  } // namespace

  /** run_chunk() on this target. */
  void ModifyChunk(const Index n_columns, double *l, const Index nr, const Index nc, double *w, const Index ldw,
                   const double *sign, double *reflectors, double *tail, const Index q, const double tolerance,
                   const Index first_column, const bool threaded)
  {
    run_chunk<1>(n_columns, l, nr, nc, w, ldw, sign, reflectors, tail, q, tolerance, first_column, threaded);
  }

  /** The most columns of C this target carries at once. */
  Index ModifyChunkColumns()
  {
    return target_chunk_columns;
  }
} // namespace warpchol::cholesky::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace warpchol::cholesky
{
  HWY_EXPORT(ModifyChunk);
  HWY_EXPORT(ModifyChunkColumns);

  namespace
  {
    /**
     * The entry of a function's dispatch table (HWY_EXPORT) for the update family's target:
     * the index Highway's ChosenTarget::GetIndex() gives when that target is chosen.
     */
    std::size_t update_dispatch_index()
    {
      const std::int64_t target = simd::target_bit(simd::Family::update);
      return hwy::Num0BitsBelowLS1Bit_Nonzero64(static_cast<std::uint64_t>(
        (HWY_CHOSEN_TARGET_SHIFT(target) | HWY_CHOSEN_TARGET_MASK_SCALAR) & HWY_CHOSEN_TARGET_MASK_TARGETS));
    }

    void run_chunk(const Index n_columns, double *l, const Index nr, const Index nc, double *w, const Index ldw,
                   const double *sign, double *reflectors, double *tail, const Index q, const double tolerance,
                   const Index first_column, const bool threaded)
    {
      (*HWY_DISPATCH_TABLE(ModifyChunk)[update_dispatch_index()])(n_columns, l, nr, nc, w, ldw, sign, reflectors,
                                                                 tail, q, tolerance, first_column, threaded);
    }

    Index chunk_columns_here()
    {
      return (*HWY_DISPATCH_TABLE(ModifyChunkColumns)[update_dispatch_index()])();
    }
  } // namespace
} // namespace warpchol::cholesky
#endif
