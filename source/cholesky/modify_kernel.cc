#include <warpchol/base/exceptions.h>
#include <warpchol/base/simd.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "modify_kernel.h"

// The kernel that applies the reflectors, once per SIMD target (Highway).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "cholesky/modify_kernel.cc"
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
     * Whether the rows below the diagonal block keep W in memory (ChunkKernel::apply_to_block)
     * rather than in registers (apply_to_groups): on 16 registers, which hold two groups'
     * only up to most_carried_in_registers columns, over short runs of reflectors.
     */
    constexpr bool w_in_memory = vector_registers < 32;

    /**
     * Columns of W a chunk takes: each chunk is one pass over the supernodes' columns. Where
     * W is carried in registers, the registers but four (a group's row of L, its sum and
     * the dot product's second sum, and one for the compiler). AVX2 keeps W in memory past
     * three columns (apply_to_block()) and takes the most, which saves passes over L; on
     * two lanes, the longer chunks were not faster.
     */
    constexpr Index target_chunk_columns =
      w_in_memory && target_lanes >= 4 ? chunk_columns : std::min<Index>(chunk_columns, vector_registers - 4);

    using Lanes = double __attribute__((vector_size(sizeof(double) * target_lanes)));

    /**
     * The most columns of W that ChunkKernel::run_by_columns() takes, on the targets that
     * keep W in memory. At rank 1 an update reads and writes each entry of L on its paths
     * once, with a few operations each: memory decides, and a walk down each column whole,
     * which the hardware prefetchers follow (and which asks for the next column as it goes),
     * moves L faster than blocks of rows across the columns, pieces of a few cache lines a
     * column apart. From two columns on, the walk reads and writes each column's rows of W
     * from the second-level cache, and the blocks are faster.
     */
    constexpr int most_columns_by_columns = w_in_memory ? 1 : 0;

    /** How many columns ahead of the one being modified a group's rows are prefetched. */
    constexpr Index prefetch_columns = 12;

    /**
     * How the reflectors of K columns keep their coefficients: as doubles, or as whole
     * vectors (the same value in every lane) that a fused multiply-add reads from memory.
     * AVX-512 broadcasts a double within the instruction. AVX2 broadcasts each double into
     * a register, once per column for all the groups, from a quarter of the memory; only
     * its walk down the columns at rank 1 (run_by_columns()), which reads each coefficient
     * once per group, goes faster with whole vectors. On two lanes a broadcast costs about
     * the operations it feeds: whole vectors.
     */
    template <int K>
    using CoefficientOf = std::conditional_t<(target_lanes <= 2 || K <= most_columns_by_columns), Lanes, double>;

    /**
     * The most columns of W that the targets of 16 registers carry in registers
     * (apply_to_groups()): two or three groups side by side (ChunkKernel::groups), each with
     * its columns, row of L and dot product, and the coefficients' broadcasts.
     */
    constexpr int most_carried_in_registers = 3;

    /**
     * The most reflectors that the targets of 16 registers apply with W in registers: a
     * longer run goes by blocks with W in memory (apply_to_block()), which take each
     * reflector over 16 groups at once, where each pass of two groups in registers reads
     * the run's coefficients and a line of L per column anew: the blocks were the faster
     * over long runs on every matrix of benchmarks/updates.sh, the registers over short.
     */
    constexpr Index most_columns_in_registers = 32;

    /** The double of a coefficient. */
    template <typename Kept>
    double scalar_of(const Kept &coefficient)
    {
      if constexpr (std::is_same_v<Kept, double>)
        return coefficient;
      else
        return coefficient[0];
    }

    /** A coefficient of value @p value. */
    template <typename Kept>
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

    /**
     * Ask for the @p n entries from @p entries to be brought in for writing: the columns
     * of a large supernode lie pages apart, where the hardware's prefetchers do not follow.
     */
    void prefetch_for_writing(const double *entries, const Index n)
    {
      for (Index i = 0; i < n; i += 8)
        __builtin_prefetch(entries + i, 1);
      __builtin_prefetch(entries + n - 1, 1);
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
     * and of W), from the supernode's first changing column q on. The diagonal block goes a
     * panel of groups at a time: the panel takes the reflectors of the columns before it,
     * a few groups side by side; then each of its groups makes its own from its rows one by
     * one, each applied at once to the group's rows below it (the others masked), and these
     * go to the panel's groups below, side by side. The groups below the diagonal block take
     * every reflector, a few side by side; the rows past the last whole group go through a
     * copy padded with zeros to a group. Every row is computed by the same operations in
     * the same order whatever the split of the rows over threads: the same bits for any
     * number of threads. Across targets the results agree to rounding: the targets of 16
     * registers keep W in memory below a group (apply_to_block()) at ranks above
     * most_carried_in_registers and over long runs of reflectors, and form the next
     * reflector's dot product from it rather than by the look-ahead of apply_to_groups().
     * At rank 1 those targets go column by column instead (run_by_columns()).
     */
    template <int K>
    struct ChunkKernel
    {
      /**
       * Coefficients per reflector j: tau, tau v (K), S v (K), and its coupling with the
       * reflector before it, tau_{j-1} v_{j-1} . S v_j (the look-ahead of apply_to_groups()).
       * A reflector maps (l, w) to (tau s - l, w - tau s v) with s = l + w . S v: both from
       * s, so that its dot product is all that one reflector passes to the next.
       */
      static constexpr Index stride = 2 * K + 2;

      using Coefficient = CoefficientOf<K>;

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
       * per group (the dot product, then the new entry and w), and independent groups fill
       * the gaps of one another's chains and share each coefficient. As many as the registers
       * hold, each group with its K columns of W, its next row of L and next dot product,
       * two registers left for the sums, and at most eight.
       */
      static constexpr int groups = std::clamp((vector_registers - 2) / (K + 2), 1, 8);

      /**
       * Interleaved partial sums of a dot product w . S v: term t goes to sum t % partial_sums.
       * Its chain of dependent operations is the longest path from one reflector to the
       * next where a group's W stays in registers over the run (apply_to_groups()): from
       * eight columns on, four chains of a quarter of it. Where W is kept in memory
       * (apply_to_block()), groups overlap one another's chains, and two sums leave the
       * registers to W.
       */
      static constexpr int partial_sums = K == 1 ? 1 : (K >= 8 && !w_in_memory) ? 4 : 2;

      /** Term t of a dot product, into @p sums (the first term of each sum but the first sets it). */
      template <typename Value, typename Scaled>
      static void add_term(const int t, Value *sums, const Value &moved, const Scaled &scaled)
      {
        const int k = t % partial_sums;
        if (k == 0 || t >= partial_sums)
          sums[k] += moved * scaled;
        else
          sums[k] = moved * scaled;
      }

      /** The dot product of @p sums, whose first started from the entry of L (the same order everywhere). */
      template <typename Value>
      static Value sum_of(const Value *sums)
      {
        if constexpr (partial_sums == 1)
          return sums[0];
        else if constexpr (partial_sums == 2)
          return sums[0] + sums[1];
        else
          return (sums[0] + sums[1]) + (sums[2] + sums[3]);
      }

      /** s = l + w . S v for one reflector. */
      template <typename Value, typename Scaled>
      static Value dot(const Value &old, const Value *carried, const Scaled *scaled)
      {
        Value sums[partial_sums];
        sums[0] = old;
        for (int t = 0; t < K; ++t)
          add_term(t, sums, carried[t], scaled[t]);
        return sum_of(sums);
      }

      /**
       * Apply the reflectors [j_begin, j_end) to G groups of rows: those of L at
       * @p rows (column stride @p ld), those of W from row @p w_row on.
       *
       * Each reflector's dot product is formed before the reflector ahead of it is applied
       * (a look-ahead): with w the carried columns before reflector j,
       *   s_{j+1} = l_{j+1} + w . S v_{j+1} - s_j (tau_j v_j . S v_{j+1}),
       * which equals l_{j+1} + w' . S v_{j+1} with w' = w - s_j tau_j v_j. The first part
       * depends on w, not on reflector j's result, so it overlaps the chain of reflector j:
       * what remains between two reflectors is one operation, not the whole dot product.
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
            // The group's entries some columns ahead.
            if (j + prefetch_columns < j_end)
              prefetch_for_writing(rows + (j + prefetch_columns) * ld, G * target_lanes);
            const Coefficient *r = reflectors + j * stride;
            Lanes              s[G];
            for (int g = 0; g < G; ++g)
              {
                s[g] = next_dot[g];
                store(rows + j * ld + g * target_lanes, r[0] * s[g] - next_old[g]);
              }
            if (j + 1 < j_end)
              {
                const Coefficient *next = r + stride;
                for (int g = 0; g < G; ++g)
                  {
                    next_old[g] = load(rows + (j + 1) * ld + g * target_lanes);
                    next_dot[g] = dot(next_old[g], carried[g], next + 1 + K) - s[g] * next[2 * K + 1];
                  }
              }
            for (int g = 0; g < G; ++g)
              for (int t = 0; t < K; ++t)
                carried[g][t] -= s[g] * r[1 + t];
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
       * the next is longer than the reflector's work. Here two reflectors at a time go over
       * all groups of the block, two groups side by side (each coefficient read once for
       * both), so that the groups' independent chains overlap; each group's W is read and
       * written once per two reflectors, and the next reflector's dot product is formed from
       * the columns just modified. The block's columns of W are copied to a buffer of fixed
       * stride, so that every address is a constant offset.
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
        for (Index j = j_begin; j < j_end;)
          {
            // Two reflectors a pass where two remain: a pass reads and writes W once.
            const Index run = std::min<Index>(2, j_end - j);
            for (Index k = j + prefetch_columns; k < std::min(j + run + prefetch_columns, j_end); ++k)
              prefetch_for_writing(rows + k * ld, n_rows);
            const Coefficient *r      = coefficients + j * stride;
            double            *column = rows + j * ld;
            Index              g      = 0;
            if (run == 2)
              {
                const Coefficient *after = j + 2 < j_end ? r + 2 * stride : nullptr;
                for (; g + 2 <= n_groups; g += 2)
                  apply_two_to_stored_groups<2>(column + g * target_lanes, ld, stored + g * target_lanes, dots + g, r,
                                                after);
                if (g < n_groups)
                  apply_two_to_stored_groups<1>(column + g * target_lanes, ld, stored + g * target_lanes, dots + g, r,
                                                after);
              }
            else
              {
                for (; g + 2 <= n_groups; g += 2)
                  apply_last_to_stored_groups<2>(column + g * target_lanes, stored + g * target_lanes, dots + g, r);
                if (g < n_groups)
                  apply_last_to_stored_groups<1>(column + g * target_lanes, stored + g * target_lanes, dots + g, r);
              }
            j += run;
          }
        for (int t = 0; t < K; ++t)
          std::copy(stored + t * block_rows, stored + t * block_rows + n_rows, w_block + t * w_stride);
      }

      /**
       * The last reflector of apply_to_block(), @p r, on P groups side by side: their entries
       * of its column at @p column, of W at @p w_rows (stride block_rows), their dot
       * products for it in @p dots.
       */
      template <int P>
      static void apply_last_to_stored_groups(double *column, double *w_rows, const Lanes *dots, const Coefficient *r)
      {
        for (int p = 0; p < P; ++p)
          store(column + p * target_lanes, r[0] * dots[p] - load(column + p * target_lanes));
#pragma GCC unroll 16
        for (int t = 0; t < K; ++t)
          for (int p = 0; p < P; ++p)
            {
              double *entry = w_rows + t * block_rows + p * target_lanes;
              store(entry, load(entry) - dots[p] * r[1 + t]);
            }
      }

      /**
       * Reflector @p r and the one after it on P groups side by side (their entries of r's
       * column at @p column, of W at @p w_rows with stride block_rows, their dot products
       * for r in @p dots), W held in registers from one to the other; then, if @p after,
       * their dot products for it. Each dot product is formed from the columns of W just
       * moved, in the order of dot().
       */
      template <int P>
      static void apply_two_to_stored_groups(double *column, const Index ld, double *w_rows, Lanes *dots,
                                             const Coefficient *r, const Coefficient *after)
      {
        const Coefficient *second = r + stride;
        Lanes              old[P], sums[P][partial_sums], moved[P][K];
        for (int p = 0; p < P; ++p)
          {
            store(column + p * target_lanes, r[0] * dots[p] - load(column + p * target_lanes));
            old[p]     = load(column + ld + p * target_lanes);
            sums[p][0] = old[p];
          }
#pragma GCC unroll 16
        for (int t = 0; t < K; ++t)
          for (int p = 0; p < P; ++p)
            {
              moved[p][t] = load(w_rows + t * block_rows + p * target_lanes) - dots[p] * r[1 + t];
              add_term(t, sums[p], moved[p][t], second[1 + K + t]);
            }
        for (int p = 0; p < P; ++p)
          {
            dots[p] = sum_of(sums[p]);
            store(column + ld + p * target_lanes, second[0] * dots[p] - old[p]);
          }
        if (after)
          for (int p = 0; p < P; ++p)
            sums[p][0] = load(column + 2 * ld + p * target_lanes);
#pragma GCC unroll 16
        for (int t = 0; t < K; ++t)
          for (int p = 0; p < P; ++p)
            {
              const Lanes twice = moved[p][t] - dots[p] * second[1 + t];
              store(w_rows + t * block_rows + p * target_lanes, twice);
              if (after)
                add_term(t, sums[p], twice, after[1 + K + t]);
            }
        if (after)
          for (int p = 0; p < P; ++p)
            dots[p] = sum_of(sums[p]);
      }

      /** Apply the reflectors [j_begin, j_end) to the whole groups of rows [row_begin, row_end) in place. */
      void apply_to_rows(const Index row_begin, const Index row_end, const Index j_begin, const Index j_end) const
      {
        if (j_begin >= j_end)
          return;
        Index i = row_begin;
        if constexpr (w_in_memory)
          if (K > most_carried_in_registers || j_end - j_begin > most_columns_in_registers)
            {
              for (; i + target_lanes <= row_end; i += block_rows)
                apply_to_block(l + i, nr, i, std::min(block_rows, row_end - i) / target_lanes, j_begin, j_end);
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
        const double r = std::sqrt(r2), denominator = alpha + r, tau = 1. + alpha / r;
        Coefficient *reflector = reflectors + j * stride;
        reflector[0]           = as_coefficient<Coefficient>(tau);
        double       coupling  = 0;
        for (int t = 0; t < K; ++t)
          {
            const double v       = row_w[t] / denominator;
            reflector[1 + t]     = as_coefficient<Coefficient>(tau * v);
            reflector[1 + K + t] = as_coefficient<Coefficient>(sign[t] * v);
            if (j > q)
              coupling += scalar_of(reflector[1 + t - stride]) * (sign[t] * v);
          }
        reflector[2 * K + 1] = as_coefficient<Coefficient>(coupling);
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
            const Lanes        s         = dot(old, carried, reflector + 1 + K);
            Lanes              changed   = reflector[0] * s - old;
            // Rows above j keep their values; row j becomes (r, 0) exactly; those below move.
            const auto below = numbers > static_cast<double>(lane);
            changed          = below ? changed : old;
            changed[lane]    = r;
            store(column, changed);
            for (int t = 0; t < K; ++t)
              {
                const Lanes moved = carried[t] - s * reflector[1 + t];
                carried[t]        = below ? moved : carried[t];
                carried[t][lane]  = 0.;
              }
          }
        for (int t = 0; t < K; ++t)
          store(w + t * ldw + i0, carried[t]);
      }

      /**
       * Modify the supernode from its local column q on, column by column: each column's
       * reflector from its row, then applied to every row below it, down the column. One
       * thread, whatever @p threaded says of run(): each row is computed the same way
       * whatever the number of threads.
       */
      void run_by_columns(const Index q, const double tolerance, const Index first_column) const
      {
        for (Index j = q; j < nc; ++j)
          {
            double *column = l + j * nr;
            double  row_w[K];
            for (int t = 0; t < K; ++t)
              row_w[t] = w[t * ldw + j];
            const double       r         = make_reflector(j, q, column[j], row_w, tolerance, first_column);
            const Coefficient *reflector = reflectors + j * stride;
            column[j]                    = r;
            for (int t = 0; t < K; ++t)
              w[t * ldw + j] = 0.;
            Index i = j + 1;
            // The next column's rows are asked for as this one's are walked: the walks
            // then run as one stream, as down a packed factor's columns.
            double *const next = j + 1 < nc ? column + nr : column;
            for (; i + target_lanes <= nr; i += target_lanes)
              {
                __builtin_prefetch(next + i, 1);
                Lanes carried[K];
                for (int t = 0; t < K; ++t)
                  carried[t] = load(w + t * ldw + i);
                store(column + i, reflected(load(column + i), carried, reflector));
                for (int t = 0; t < K; ++t)
                  store(w + t * ldw + i, carried[t]);
              }
            double scalar[1 + 2 * K];
            for (int k = 0; k < 1 + 2 * K; ++k)
              scalar[k] = scalar_of(reflector[k]);
            for (; i < nr; ++i)
              {
                double carried[K];
                for (int t = 0; t < K; ++t)
                  carried[t] = w[t * ldw + i];
                column[i] = reflected(column[i], carried, scalar);
                for (int t = 0; t < K; ++t)
                  w[t * ldw + i] = carried[t];
              }
          }
      }

      /**
       * Reflector @p r (tau, v, S v) on a row group or a row, @p old of L and its columns of
       * W @p carried (moved in place): returns the new entries of L.
       */
      template <typename Value, typename Scaled>
      static Value reflected(const Value &old, Value *carried, const Scaled *r)
      {
        const Value s = dot(old, carried, r + 1 + K);
        for (int t = 0; t < K; ++t)
          carried[t] -= s * r[1 + t];
        return r[0] * s - old;
      }

      /**
       * Modify the supernode from its local column q on, the rows below the diagonal
       * block split over threads if @p threaded.
       */
      void run(const Index q, const double tolerance, const Index first_column, const bool threaded) const
      {
        if constexpr (K <= most_columns_by_columns)
          {
            run_by_columns(q, tolerance, first_column);
            return;
          }
        const Index     whole_end    = q + (nr - q) / target_lanes * target_lanes;
        constexpr Index side_by_side = groups * target_lanes;
        // The diagonal block's rows a panel at a time: the reflectors of the columns before
        // the panel with groups side by side; then group by group, each group makes its
        // columns' reflectors, which go at once to the panel's rows below it, side by side
        // (not one group at a time as each group reaches them).
        constexpr Index panel_rows = 4 * side_by_side;
        Index           i0         = q;
        while (i0 < nc && i0 < whole_end)
          {
            const Index panel_end = std::min(i0 + panel_rows, whole_end);
            apply_to_rows(i0, panel_end, q, i0);
            for (; i0 < panel_end; i0 += target_lanes)
              {
                diagonal_group(l + i0, nr, i0, i0, q, tolerance, first_column);
                if (i0 < nc)
                  apply_to_rows(i0 + target_lanes, panel_end, i0, std::min(i0 + target_lanes, nc));
              }
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
    void run_chunk_of(const Index n_columns, const SupernodeChunk &chunk)
    {
      if constexpr (K < target_chunk_columns)
        if (n_columns > K)
          {
            run_chunk_of<K + 1>(n_columns, chunk);
            return;
          }
      // The reflectors' room aligned to a vector (it has a vector of doubles to spare).
      using Coefficient                  = typename ChunkKernel<K>::Coefficient;
      constexpr std::uintptr_t alignment = alignof(Coefficient);
      const auto               aligned   = reinterpret_cast<Coefficient *>(
        (reinterpret_cast<std::uintptr_t>(chunk.reflectors) + alignment - 1) / alignment * alignment);
      const ChunkKernel<K> kernel{chunk.l, chunk.nr, chunk.nc, chunk.w, chunk.ldw, chunk.sign, aligned, chunk.tail};
      kernel.run(chunk.q, chunk.tolerance, chunk.first_column, chunk.threaded);
    }

  } // namespace

  /** run_chunk() on this target. */
  void ModifyChunk(const Index n_columns, const SupernodeChunk &chunk)
  {
    run_chunk_of<1>(n_columns, chunk);
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

  void run_chunk(const Index n_columns, const SupernodeChunk &chunk)
  {
    (*HWY_DISPATCH_TABLE(ModifyChunk)[simd::dispatch_index(simd::Family::update)])(n_columns, chunk);
  }

  Index chunk_columns_here()
  {
    return (*HWY_DISPATCH_TABLE(ModifyChunkColumns)[simd::dispatch_index(simd::Family::update)])();
  }
} // namespace warpchol::cholesky
#endif
