#include "scaled_solve.h"

#include <algorithm>
#include <cmath>
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

    /** Columns a pass carries at once: each row of x is loaded and stored once per block. */
    constexpr int block_columns = 8;
  } // namespace
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
    using FloatTag = hn::ScalableTag<float>;
    using Floats   = hn::Vec<FloatTag>;

    inline Floats load(const FloatTag d, const float *p)
    {
      return hn::LoadU(d, p);
    }

    inline Floats load(const FloatTag d, const Half *p)
    {
      const hn::Rebind<hwy::float16_t, FloatTag> dh;
      return hn::PromoteTo(d, hn::LoadU(dh, p));
    }

    /** Room for a vector of floats on any target. */
    constexpr std::size_t max_lanes = scaled_solve_padding;

    /**
     * The B x B block at @p l (column stride @p ld) in single precision, column by column
     * (each column read as a whole vector: the padding keeps that inside the arrays).
     */
    template <int B, typename Stored>
    inline void load_block(const Stored *l, const Index ld, float (&block)[B][B])
    {
      const FloatTag  d;
      const Index     lanes = static_cast<Index>(hn::Lanes(d));
      HWY_ALIGN float column[2 * max_lanes] = {};
      for (int k = 0; k < B; ++k)
        {
          // As many vectors as B rows take (two on a 128-bit target).
          for (Index i = 0; i < B; i += lanes)
            hn::Store(load(d, l + k * ld + i), d, column + i);
          for (int i = 0; i < B; ++i)
            block[k][i] = column[i];
        }
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
      const hn::ScalableTag<double>            d;
      const hn::Rebind<float, decltype(d)> df;
      const Index                              lanes = static_cast<Index>(hn::Lanes(d));
      const auto                               f     = hn::Set(d, factor);
      Index                                    i     = 0;
      for (; i + lanes <= count; i += lanes)
        hn::StoreU(hn::DemoteTo(df, hn::Mul(hn::LoadU(d, values + i), f)), df, stored + i);
      for (; i < count; ++i)
        stored[i] = static_cast<float>(values[i] * factor);
    }

    void scale_into(const double *values, const Index count, const double factor, Half *stored)
    {
      const hn::ScalableTag<double>                  d;
      const hn::Rebind<float, decltype(d)>           df;
      const hn::Rebind<hwy::float16_t, decltype(d)>  dh;
      const Index                                    lanes = static_cast<Index>(hn::Lanes(d));
      const auto                                     f     = hn::Set(d, factor);
      Index                                          i     = 0;
      for (; i + lanes <= count; i += lanes)
        hn::StoreU(hn::DemoteTo(dh, hn::DemoteTo(df, hn::Mul(hn::LoadU(d, values + i), f))), dh, stored + i);
      for (; i < count; ++i)
        stored[i] = half_from_float(static_cast<float>(values[i] * factor));
    }

    template <typename Stored>
    void round_columns_of(const double *values, const Index nr, const Index nc, const Index q, Stored *stored,
                          float *scale, float *inverse_diagonal)
    {
      for (Index j = q; j < nc; ++j)
        {
          const double *column = values + j * nr;
          // A power of two at least the largest entry: the scaling itself rounds nothing.
          int exponent;
          std::frexp(largest_size(column + j, nr - j), &exponent);
          const double factor = std::ldexp(1., -exponent);
          for (Index i = 0; i < j; ++i)
            from_float(0.f, stored[j * nr + i]);
          scale_into(column + j, nr - j, factor, stored + j * nr + j);
          scale[j]            = std::ldexp(1.f, exponent);
          inverse_diagonal[j] = static_cast<float>(1. / (column[j] * factor));
        }
    }

    /**
     * target[r - r0] -= sum_k L(r, k) t[k] for the rows [r0, r1) of the B columns at
     * @p columns (column stride @p ld).
     */
    template <int B, typename Stored>
    void subtract_columns(const Stored *columns, const Index ld, const Index r0, const Index r1, const float *t,
                          float *target, const Stored *ahead)
    {
      const FloatTag d;
      const Index    lanes = static_cast<Index>(hn::Lanes(d));
      Floats         factor[B];
      for (int k = 0; k < B; ++k)
        factor[k] = hn::Set(d, t[k]);
      Index r = r0;
      for (; r + lanes <= r1; r += lanes)
        {
          // Blocks of eight short columns are short streams the prefetchers do not learn
          // in time: fetch the next block's rows ahead.
          if (ahead != nullptr)
            for (int k = 0; k < B; ++k)
              hwy::Prefetch(ahead + k * ld + r);
          Floats y = hn::LoadU(d, target + (r - r0));
          for (int k = 0; k < B; ++k)
            y = hn::NegMulAdd(load(d, columns + k * ld + r), factor[k], y);
          hn::StoreU(y, d, target + (r - r0));
        }
      if (r < r1)
        {
          // A whole vector, read past the rows (the padding keeps it inside the arrays);
          // only the rows' lanes are written back.
          HWY_ALIGN float y[max_lanes];
          Floats          v = hn::LoadU(d, target + (r - r0));
          for (int k = 0; k < B; ++k)
            v = hn::NegMulAdd(load(d, columns + k * ld + r), factor[k], v);
          hn::Store(v, d, y);
          std::memcpy(target + (r - r0), y, static_cast<std::size_t>(r1 - r) * sizeof(float));
        }
    }

    /** s[k] += sum_r L(r, k) source[r - r0] over the rows [r0, r1) of the B columns at @p columns. */
    template <int B, typename Stored>
    void add_dots(const Stored *columns, const Index ld, const Index r0, const Index r1, const float *source,
                  float *s, const Stored *ahead)
    {
      const FloatTag d;
      const Index    lanes = static_cast<Index>(hn::Lanes(d));
      Floats         even[B], odd[B];
      for (int k = 0; k < B; ++k)
        even[k] = odd[k] = hn::Zero(d);
      Index r = r0;
      // Two sums per column: twice the chains in flight.
      for (; r + 2 * lanes <= r1; r += 2 * lanes)
        {
          // The backward pass walks the factor downwards in memory, block by block, where
          // the hardware's prefetchers lose the stream: fetch the next block's rows ahead.
          if (ahead != nullptr)
            for (int k = 0; k < B; ++k)
              hwy::Prefetch(ahead + k * ld + r);
          const Floats x0 = hn::LoadU(d, source + (r - r0)), x1 = hn::LoadU(d, source + (r - r0) + lanes);
          for (int k = 0; k < B; ++k)
            {
              even[k] = hn::MulAdd(load(d, columns + k * ld + r), x0, even[k]);
              odd[k]  = hn::MulAdd(load(d, columns + k * ld + r + lanes), x1, odd[k]);
            }
        }
      for (; r + lanes <= r1; r += lanes)
        {
          const Floats x = hn::LoadU(d, source + (r - r0));
          for (int k = 0; k < B; ++k)
            even[k] = hn::MulAdd(load(d, columns + k * ld + r), x, even[k]);
        }
      if (r < r1)
        {
          // Read past the rows as above; the lanes past them are zeros of x (L's entries
          // there are finite: scaled entries of L, zeros above its diagonal, padding).
          const Floats x = hn::IfThenElseZero(hn::FirstN(d, static_cast<std::size_t>(r1 - r)),
                                              hn::LoadU(d, source + (r - r0)));
          for (int k = 0; k < B; ++k)
            odd[k] = hn::MulAdd(load(d, columns + k * ld + r), x, odd[k]);
        }
      for (int k = 0; k < B; ++k)
        s[k] += hn::GetLane(hn::SumOfLanes(d, hn::Add(even[k], odd[k])));
    }

    /** The forward pass over the B columns from @p j0. */
    template <int B, typename Stored>
    void forward_block(const Stored *l, const Index nr, const Index nc, const Index j0, const float *scale,
                       const float *inverse_diagonal, float *own, float *below)
    {
      // With column j scaled by scale[j]: L = S D, t_j = (S^-1-solved) x_j * scale[j].
      float t[B], block[B][B];
      load_block<B>(l + j0 * nr + j0, nr, block);
      for (int k = 0; k < B; ++k)
        {
          t[k] = own[j0 + k] * inverse_diagonal[j0 + k];
          for (int k2 = k + 1; k2 < B; ++k2)
            own[j0 + k2] -= block[k][k2] * t[k];
        }
      const Stored *ahead = j0 + B < nc ? l + (j0 + B) * nr : nullptr;
      subtract_columns<B>(l + j0 * nr, nr, j0 + B, nc, t, own + j0 + B, ahead);
      subtract_columns<B>(l + j0 * nr, nr, nc, nr, t, below, ahead);
      for (int k = 0; k < B; ++k)
        own[j0 + k] = t[k] / scale[j0 + k];
    }

    /** The backward pass over the B columns from @p j0 (those after them solved). */
    template <int B, typename Stored>
    void backward_block(const Stored *l, const Index nr, const Index nc, const Index j0, const float *scale,
                        const float *inverse_diagonal, float *own, const float *below)
    {
      // The block after this one (the columns before it), whose rows are read next.
      const Stored *ahead = j0 >= block_columns ? l + (j0 - block_columns) * nr : nullptr;
      float s[B] = {}, block[B][B];
      add_dots<B>(l + j0 * nr, nr, j0 + B, nc, own + j0 + B, s, ahead);
      add_dots<B>(l + j0 * nr, nr, nc, nr, below, s, ahead);
      load_block<B>(l + j0 * nr + j0, nr, block);
      for (int k = B - 1; k >= 0; --k)
        {
          const Index j = j0 + k;
          float       v = own[j] / scale[j] - s[k];
          for (int k2 = k + 1; k2 < B; ++k2)
            v -= block[k][k2] * own[j0 + k2];
          own[j] = v * inverse_diagonal[j];
        }
    }

    /** forward_block<count>() for the last @p count (< block_columns) columns, from @p j0. */
    template <int B, typename Stored>
    void forward_last(const Index count, const Stored *l, const Index nr, const Index nc, const Index j0,
                      const float *scale, const float *inverse_diagonal, float *own, float *below)
    {
      if constexpr (B > 1)
        if (count < B)
          return forward_last<B - 1>(count, l, nr, nc, j0, scale, inverse_diagonal, own, below);
      forward_block<B>(l, nr, nc, j0, scale, inverse_diagonal, own, below);
    }

    template <int B, typename Stored>
    void backward_last(const Index count, const Stored *l, const Index nr, const Index nc, const Index j0,
                       const float *scale, const float *inverse_diagonal, float *own, const float *below)
    {
      if constexpr (B > 1)
        if (count < B)
          return backward_last<B - 1>(count, l, nr, nc, j0, scale, inverse_diagonal, own, below);
      backward_block<B>(l, nr, nc, j0, scale, inverse_diagonal, own, below);
    }

    template <typename Stored>
    void forward_of(const Stored *l, const Index nr, const Index nc, const float *scale,
                    const float *inverse_diagonal, float *own, float *below)
    {
      std::fill(below, below + (nr - nc), 0.f);
      Index j0 = 0;
      for (; j0 + block_columns <= nc; j0 += block_columns)
        forward_block<block_columns>(l, nr, nc, j0, scale, inverse_diagonal, own, below);
      if (j0 < nc)
        forward_last<block_columns - 1>(nc - j0, l, nr, nc, j0, scale, inverse_diagonal, own, below);
    }

    template <typename Stored>
    void backward_of(const Stored *l, const Index nr, const Index nc, const float *scale,
                     const float *inverse_diagonal, float *own, const float *below)
    {
      // The same blocks as the forward pass, from the last.
      const Index whole = nc / block_columns * block_columns;
      if (whole < nc)
        backward_last<block_columns - 1>(nc - whole, l, nr, nc, whole, scale, inverse_diagonal, own, below);
      for (Index j0 = whole - block_columns; j0 >= 0; j0 -= block_columns)
        backward_block<block_columns>(l, nr, nc, j0, scale, inverse_diagonal, own, below);
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
                   float *own, float *below)
  {
    forward_of(l, nr, nc, scale, inverse_diagonal, own, below);
  }

  void ForwardSingle(const float *l, const Index nr, const Index nc, const float *scale,
                     const float *inverse_diagonal, float *own, float *below)
  {
    forward_of(l, nr, nc, scale, inverse_diagonal, own, below);
  }

  void BackwardHalf(const Half *l, const Index nr, const Index nc, const float *scale, const float *inverse_diagonal,
                    float *own, const float *below)
  {
    backward_of(l, nr, nc, scale, inverse_diagonal, own, below);
  }

  void BackwardSingle(const float *l, const Index nr, const Index nc, const float *scale,
                      const float *inverse_diagonal, float *own, const float *below)
  {
    backward_of(l, nr, nc, scale, inverse_diagonal, own, below);
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
                      const float *inverse_diagonal, float *own, float *below)
  {
    HWY_DYNAMIC_DISPATCH(ForwardHalf)(l, nr, nc, scale, inverse_diagonal, own, below);
  }

  void forward_scaled(const float *l, const Index nr, const Index nc, const float *scale,
                      const float *inverse_diagonal, float *own, float *below)
  {
    HWY_DYNAMIC_DISPATCH(ForwardSingle)(l, nr, nc, scale, inverse_diagonal, own, below);
  }

  void backward_scaled(const Half *l, const Index nr, const Index nc, const float *scale,
                       const float *inverse_diagonal, float *own, const float *below)
  {
    HWY_DYNAMIC_DISPATCH(BackwardHalf)(l, nr, nc, scale, inverse_diagonal, own, below);
  }

  void backward_scaled(const float *l, const Index nr, const Index nc, const float *scale,
                       const float *inverse_diagonal, float *own, const float *below)
  {
    HWY_DYNAMIC_DISPATCH(BackwardSingle)(l, nr, nc, scale, inverse_diagonal, own, below);
  }
} // namespace warpchol::cholesky
#endif
