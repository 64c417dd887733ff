#include "scaled_solve.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include <warpchol/base/simd.h>

// What every target shares, compiled once (this file is included again per SIMD target).
#ifndef warpchol_cholesky_scaled_solve_shared
#define warpchol_cholesky_scaled_solve_shared
namespace warpchol::cholesky
{
  Half half_from_float(const float x)
  {
    std::uint32_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    const std::uint32_t sign = (bits >> 16) & 0x8000u, magnitude = bits & 0x7fffffffu;
    std::uint16_t       half;
    if (magnitude >= 0x7f800000u) // infinity or NaN (kept a NaN)
      half = static_cast<std::uint16_t>(sign | 0x7c00u | (magnitude > 0x7f800000u ? 0x200u : 0u));
    else if (magnitude >= 0x477ff000u) // rounds past 65504
      half = static_cast<std::uint16_t>(sign | 0x7c00u);
    else if (magnitude < 0x38800000u) // below half's normal range: a multiple of 2^-24
      {
        float       value;
        const float size = std::abs(x);
        value            = std::nearbyint(size * 16777216.f); // ties to even in the default mode
        half             = static_cast<std::uint16_t>(sign | static_cast<std::uint32_t>(value));
      }
    else
      {
        // Round the 23-bit mantissa to 10 bits, ties to even; a carry moves into the exponent.
        const std::uint32_t rebased = magnitude - 0x38000000u;
        const std::uint32_t rounded = rebased + 0xfffu + ((rebased >> 13) & 1u);
        half                        = static_cast<std::uint16_t>(sign | (rounded >> 13));
      }
    Half result;
    std::memcpy(&result, &half, sizeof half);
    return result;
  }

  float float_from_half(const Half h)
  {
    std::uint16_t half;
    std::memcpy(&half, &h, sizeof half);
    const std::uint32_t sign = static_cast<std::uint32_t>(half & 0x8000u) << 16, exponent = (half >> 10) & 0x1fu,
                        mantissa = half & 0x3ffu;
    if (exponent == 0)
      {
        const float size = static_cast<float>(mantissa) * 0x1p-24f; // exact
        return sign != 0 ? -size : size;
      }
    const std::uint32_t bits =
      sign | (exponent == 31 ? 0x7f800000u | (mantissa << 13) : ((exponent + 112) << 23) | (mantissa << 13));
    float result;
    std::memcpy(&result, &bits, sizeof result);
    return result;
  }

  namespace
  {
    inline void from_float(const float x, float &stored)
    {
      stored = x;
    }

    inline void from_float(const float x, Half &stored)
    {
      stored = half_from_float(x);
    }

    /** The tiles of block j0 of a supernode of @p nr rows: its rows from j0 on, padded to whole tiles. */
    inline Index block_tiles(const Index nr, const Index j0)
    {
      return (nr - j0 + scaled_tile_rows - 1) / scaled_tile_rows;
    }

    /** The entries of block j0 of a supernode of @p nr rows and @p nc columns in the copy. */
    inline Index block_entries(const Index nr, const Index nc, const Index j0)
    {
      return std::min(scaled_block_columns, nc - j0) * block_tiles(nr, j0) * scaled_tile_rows;
    }
  } // namespace

  Index scaled_copy_entries(const Index nr, const Index nc)
  {
    Index entries = 0;
    for (Index j0 = 0; j0 < nc; j0 += scaled_block_columns)
      entries += block_entries(nr, nc, j0);
    return entries;
  }
} // namespace warpchol::cholesky
#endif

// The kernels, once per SIMD target (Highway's foreach_target).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "cholesky/scaled_solve.cc"
#include <hwy/foreach_target.h>
#include <hwy/cache_control.h>
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace warpchol::cholesky::HWY_NAMESPACE
{
  namespace hn = hwy::HWY_NAMESPACE;

  namespace
  {
    /** At most a tile's rows per vector: a tile is one vector on AVX2 and AVX-512, two on SSE4. */
    using FloatTag = hn::CappedTag<float, scaled_tile_rows>;
    using Floats   = hn::Vec<FloatTag>;
    constexpr int tile = static_cast<int>(scaled_tile_rows);

    inline Floats load(const FloatTag d, const float *p)
    {
      return hn::LoadU(d, p);
    }

    inline Floats load(const FloatTag d, const Half *p)
    {
      const hn::Rebind<hwy::float16_t, FloatTag> dh;
      return hn::PromoteTo(d, hn::LoadU(dh, p));
    }

    /** The first tile of a block (its diagonal block on top) in single precision: first[k][i] = L(j0 + i, j0 + k). */
    template <int B, typename Stored>
    inline void load_first_tile(const Stored *l, float (&first)[B][scaled_tile_rows])
    {
      const FloatTag d;
      const int      lanes = static_cast<int>(hn::Lanes(d));
      for (int k = 0; k < B; ++k)
        for (int i = 0; i < tile; i += lanes)
          hn::StoreU(load(d, l + k * tile + i), d, first[k] + i);
    }

    /**
     * A hint to bring into the cache the B x tile entries that start @p entries_below entries
     * before @p from (an address computed as an integer: it may lie before the copy).
     */
    template <int B, typename Stored>
    inline void prefetch_tile(const Stored *from, const Index entries_below)
    {
      const std::uintptr_t start =
        reinterpret_cast<std::uintptr_t>(from) - static_cast<std::uintptr_t>(entries_below) * sizeof(Stored);
      for (std::uintptr_t byte = 0; byte < B * tile * sizeof(Stored); byte += 64)
        hwy::Prefetch(reinterpret_cast<const char *>(start + byte));
    }

    /** The largest |value| of @p count doubles. */
    double largest_size(const double *values, const Index count)
    {
      const hn::ScalableTag<double> d;
      const Index                   lanes = static_cast<Index>(hn::Lanes(d));
      auto                          top   = hn::Zero(d);
      Index                         i     = 0;
      for (; i + lanes <= count; i += lanes)
        top = hn::Max(top, hn::Abs(hn::LoadU(d, values + i)));
      double result = hn::GetLane(hn::MaxOfLanes(d, top));
      for (; i < count; ++i)
        result = std::max(result, std::abs(values[i]));
      return result;
    }

    /** stored[i] = values[i] * factor, rounded, for i < count. */
    void scale_into(const double *values, const Index count, const double factor, float *stored)
    {
      const hn::ScalableTag<double>        d;
      const hn::Rebind<float, decltype(d)> df;
      const Index                          lanes = static_cast<Index>(hn::Lanes(d));
      const auto                           f     = hn::Set(d, factor);
      Index                                i     = 0;
      for (; i + lanes <= count; i += lanes)
        hn::StoreU(hn::DemoteTo(df, hn::Mul(hn::LoadU(d, values + i), f)), df, stored + i);
      for (; i < count; ++i)
        stored[i] = static_cast<float>(values[i] * factor);
    }

    void scale_into(const double *values, const Index count, const double factor, Half *stored)
    {
      const hn::ScalableTag<double>                 d;
      const hn::Rebind<float, decltype(d)>          df;
      const hn::Rebind<hwy::float16_t, decltype(d)> dh;
      const Index                                   lanes = static_cast<Index>(hn::Lanes(d));
      const auto                                    f     = hn::Set(d, factor);
      Index                                         i     = 0;
      for (; i + lanes <= count; i += lanes)
        hn::StoreU(hn::DemoteTo(dh, hn::DemoteTo(df, hn::Mul(hn::LoadU(d, values + i), f))), dh, stored + i);
      for (; i < count; ++i)
        stored[i] = half_from_float(static_cast<float>(values[i] * factor));
    }

    /**
     * Block j0 (width B) of a supernode into the copy at @p stored: column j = j0 + k
     * scaled by @p factor[k], its rows [j0, nr) in tiles, zeros above the diagonal and past nr.
     */
    template <typename Stored>
    void round_block(const double *values, const Index nr, const Index j0, const Index b, const double *factor,
                     Stored *stored)
    {
      for (Index t = 0; t < block_tiles(nr, j0); ++t)
        for (Index k = 0; k < b; ++k)
          {
            const Index   j      = j0 + k;
            const double *column = values + j * nr;
            Stored       *to     = stored + (t * b + k) * tile;
            const Index   r0     = j0 + t * tile;
            if (r0 >= j && r0 + tile <= nr)
              scale_into(column + r0, tile, factor[k], to);
            else
              for (Index i = 0; i < tile; ++i)
                {
                  const Index r = r0 + i;
                  from_float(r >= j && r < nr ? static_cast<float>(column[r] * factor[k]) : 0.f, to[i]);
                }
          }
    }

    template <typename Stored>
    void round_columns_of(const double *values, const Index nr, const Index nc, const Index q, Stored *stored,
                          float *scale, float *inverse_diagonal)
    {
      Stored *block = stored;
      for (Index j0 = 0; j0 < nc; j0 += scaled_block_columns)
        {
          const Index b = std::min(scaled_block_columns, nc - j0);
          if (j0 + b > q)
            {
              double factor[scaled_block_columns];
              for (Index k = 0; k < b; ++k)
                {
                  const Index   j      = j0 + k;
                  const double *column = values + j * nr;
                  // A power of two at least the largest entry: the scaling itself rounds nothing.
                  int exponent;
                  std::frexp(largest_size(column + j, nr - j), &exponent);
                  factor[k]           = std::ldexp(1., -exponent);
                  scale[j]            = std::ldexp(1.f, exponent);
                  inverse_diagonal[j] = static_cast<float>(1. / (column[j] * factor[k]));
                }
              round_block(values, nr, j0, b, factor, block);
            }
          block += block_entries(nr, nc, j0);
        }
    }

    /**
     * The forward pass over block j0 (width B, its tiles at @p l) of a supernode of nr rows:
     * work[j0, j0 + B) solved with the block's diagonal, then the rows below it updated.
     */
    template <int B, typename Stored>
    void forward_block(const Stored *l, const Index nr, const Index j0, const float *scale,
                       const float *inverse_diagonal, float *work)
    {
      const FloatTag d;
      const int      lanes = static_cast<int>(hn::Lanes(d));
      // With column j scaled by scale[j]: L = S D, t_j = (S^-1-solved) x_j * scale[j].
      float t[B], first[B][scaled_tile_rows];
      load_first_tile<B>(l, first);
      for (int k = 0; k < B; ++k)
        {
          t[k] = work[j0 + k] * inverse_diagonal[j0 + k];
          for (int i = k + 1; i < B; ++i)
            work[j0 + i] -= first[k][i] * t[k];
        }
      Floats factor[B];
      for (int k = 0; k < B; ++k)
        factor[k] = hn::Set(d, t[k]);
      const Index n_tiles = block_tiles(nr, j0);
      // The first tile's first B rows are the block's own, solved above: kept.
      for (int i = 0; i < tile; i += lanes)
        {
          Floats y = hn::LoadU(d, work + j0 + i);
          Floats v = y;
          for (int k = 0; k < B; ++k)
            v = hn::NegMulAdd(load(d, l + k * tile + i), factor[k], v);
          hn::StoreU(hn::IfThenElse(hn::FirstN(d, static_cast<std::size_t>(std::max(0, B - i))), y, v), d,
                     work + j0 + i);
        }
      for (Index t0 = 1; t0 < n_tiles; ++t0)
        {
          const Stored *tile_values = l + t0 * B * tile;
          float        *y_rows      = work + j0 + t0 * tile;
          for (int i = 0; i < tile; i += lanes)
            {
              Floats y = hn::LoadU(d, y_rows + i);
              for (int k = 0; k < B; ++k)
                y = hn::NegMulAdd(load(d, tile_values + k * tile + i), factor[k], y);
              hn::StoreU(y, d, y_rows + i);
            }
        }
      for (int k = 0; k < B; ++k)
        work[j0 + k] = t[k] / scale[j0 + k];
    }

    /** The backward pass over block j0 (width B, its tiles at @p l): the rows after it solved. */
    template <int B, typename Stored>
    void backward_block(const Stored *l, const Index nr, const Index j0, const float *scale,
                        const float *inverse_diagonal, float *work)
    {
      const FloatTag d;
      const int      lanes = static_cast<int>(hn::Lanes(d));
      Floats         sum[B];
      for (int k = 0; k < B; ++k)
        sum[k] = hn::Zero(d);
      const Index n_tiles = block_tiles(nr, j0);
      // The pass walks the copy downwards, block by block, which the hardware's prefetchers
      // do not follow: each tile asks for the one as far below it as this block is long,
      // which is in the block solved next (or the previous supernode's last), and the first
      // tile asks for the one more tile that block may have.
      const Index entries = B * n_tiles * tile;
      prefetch_tile<B>(l, entries + B * tile);
      prefetch_tile<B>(l, entries);
      // The first tile without the block's own rows (zeros of x in their lanes); the
      // rows past nr are zeros of L.
      for (int i = 0; i < tile; i += lanes)
        {
          const Floats x = hn::IfThenZeroElse(hn::FirstN(d, static_cast<std::size_t>(std::max(0, B - i))),
                                              hn::LoadU(d, work + j0 + i));
          for (int k = 0; k < B; ++k)
            sum[k] = hn::MulAdd(load(d, l + k * tile + i), x, sum[k]);
        }
      for (Index t0 = 1; t0 < n_tiles; ++t0)
        {
          const Stored *tile_values = l + t0 * B * tile;
          prefetch_tile<B>(tile_values, entries);
          const float  *x_rows      = work + j0 + t0 * tile;
          for (int i = 0; i < tile; i += lanes)
            {
              const Floats x = hn::LoadU(d, x_rows + i);
              for (int k = 0; k < B; ++k)
                sum[k] = hn::MulAdd(load(d, tile_values + k * tile + i), x, sum[k]);
            }
        }
      float first[B][scaled_tile_rows];
      load_first_tile<B>(l, first);
      for (int k = B - 1; k >= 0; --k)
        {
          const Index j = j0 + k;
          float       v = work[j] / scale[j] - hn::GetLane(hn::SumOfLanes(d, sum[k]));
          for (int i = k + 1; i < B; ++i)
            v -= first[k][i] * work[j0 + i];
          work[j] = v * inverse_diagonal[j];
        }
    }

    /** forward_block<count>() for a last block of @p count (< scaled_block_columns) columns. */
    template <int B, typename Stored>
    void forward_last(const Index count, const Stored *l, const Index nr, const Index j0, const float *scale,
                      const float *inverse_diagonal, float *work)
    {
      if constexpr (B > 1)
        if (count < B)
          return forward_last<B - 1>(count, l, nr, j0, scale, inverse_diagonal, work);
      forward_block<B>(l, nr, j0, scale, inverse_diagonal, work);
    }

    template <int B, typename Stored>
    void backward_last(const Index count, const Stored *l, const Index nr, const Index j0, const float *scale,
                       const float *inverse_diagonal, float *work)
    {
      if constexpr (B > 1)
        if (count < B)
          return backward_last<B - 1>(count, l, nr, j0, scale, inverse_diagonal, work);
      backward_block<B>(l, nr, j0, scale, inverse_diagonal, work);
    }

    constexpr int block_columns = static_cast<int>(scaled_block_columns);

    template <typename Stored>
    void forward_of(const Stored *l, const Index nr, const Index nc, const float *scale,
                    const float *inverse_diagonal, float *work)
    {
      Index j0 = 0;
      for (; j0 + block_columns <= nc; j0 += block_columns)
        {
          forward_block<block_columns>(l, nr, j0, scale, inverse_diagonal, work);
          l += block_entries(nr, nc, j0);
        }
      if (j0 < nc)
        forward_last<block_columns - 1>(nc - j0, l, nr, j0, scale, inverse_diagonal, work);
    }

    template <typename Stored>
    void backward_of(const Stored *l, const Index nr, const Index nc, const float *scale,
                     const float *inverse_diagonal, float *work)
    {
      // The same blocks as the forward pass, from the last: the copy walked downwards,
      // each block upwards.
      const Index whole = nc / block_columns * block_columns;
      const Stored *block = l + scaled_copy_entries(nr, nc);
      if (whole < nc)
        {
          block -= block_entries(nr, nc, whole);
          backward_last<block_columns - 1>(nc - whole, block, nr, whole, scale, inverse_diagonal, work);
        }
      for (Index j0 = whole - block_columns; j0 >= 0; j0 -= block_columns)
        {
          block -= block_entries(nr, nc, j0);
          backward_block<block_columns>(block, nr, j0, scale, inverse_diagonal, work);
        }
    }
  } // namespace

  void RoundColumnsHalf(const double *values, const Index nr, const Index nc, const Index q, Half *stored,
                        float *scale, float *inverse_diagonal)
  {
    round_columns_of(values, nr, nc, q, stored, scale, inverse_diagonal);
  }

  void RoundColumnsSingle(const double *values, const Index nr, const Index nc, const Index q, float *stored,
                          float *scale, float *inverse_diagonal)
  {
    round_columns_of(values, nr, nc, q, stored, scale, inverse_diagonal);
  }

  void ForwardHalf(const Half *l, const Index nr, const Index nc, const float *scale, const float *inverse_diagonal,
                   float *work)
  {
    forward_of(l, nr, nc, scale, inverse_diagonal, work);
  }

  void ForwardSingle(const float *l, const Index nr, const Index nc, const float *scale,
                     const float *inverse_diagonal, float *work)
  {
    forward_of(l, nr, nc, scale, inverse_diagonal, work);
  }

  void BackwardHalf(const Half *l, const Index nr, const Index nc, const float *scale, const float *inverse_diagonal,
                    float *work)
  {
    backward_of(l, nr, nc, scale, inverse_diagonal, work);
  }

  void BackwardSingle(const float *l, const Index nr, const Index nc, const float *scale,
                      const float *inverse_diagonal, float *work)
  {
    backward_of(l, nr, nc, scale, inverse_diagonal, work);
  }
} // namespace warpchol::cholesky::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace warpchol::cholesky
{
  HWY_EXPORT(RoundColumnsHalf);
  HWY_EXPORT(RoundColumnsSingle);
  HWY_EXPORT(ForwardHalf);
  HWY_EXPORT(ForwardSingle);
  HWY_EXPORT(BackwardHalf);
  HWY_EXPORT(BackwardSingle);

  void round_columns(const double *values, const Index nr, const Index nc, const Index q, Half *stored,
                     float *scale, float *inverse_diagonal)
  {
    simd::use_target_from_environment();
    HWY_DYNAMIC_DISPATCH(RoundColumnsHalf)(values, nr, nc, q, stored, scale, inverse_diagonal);
  }

  void round_columns(const double *values, const Index nr, const Index nc, const Index q, float *stored,
                     float *scale, float *inverse_diagonal)
  {
    simd::use_target_from_environment();
    HWY_DYNAMIC_DISPATCH(RoundColumnsSingle)(values, nr, nc, q, stored, scale, inverse_diagonal);
  }

  void forward_scaled(const Half *l, const Index nr, const Index nc, const float *scale,
                      const float *inverse_diagonal, float *work)
  {
    HWY_DYNAMIC_DISPATCH(ForwardHalf)(l, nr, nc, scale, inverse_diagonal, work);
  }

  void forward_scaled(const float *l, const Index nr, const Index nc, const float *scale,
                      const float *inverse_diagonal, float *work)
  {
    HWY_DYNAMIC_DISPATCH(ForwardSingle)(l, nr, nc, scale, inverse_diagonal, work);
  }

  void backward_scaled(const Half *l, const Index nr, const Index nc, const float *scale,
                       const float *inverse_diagonal, float *work)
  {
    HWY_DYNAMIC_DISPATCH(BackwardHalf)(l, nr, nc, scale, inverse_diagonal, work);
  }

  void backward_scaled(const float *l, const Index nr, const Index nc, const float *scale,
                       const float *inverse_diagonal, float *work)
  {
    HWY_DYNAMIC_DISPATCH(BackwardSingle)(l, nr, nc, scale, inverse_diagonal, work);
  }
} // namespace warpchol::cholesky
#endif
