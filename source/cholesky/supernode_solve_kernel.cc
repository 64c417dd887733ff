#include "supernode_solve_kernel.h"

#include <algorithm>

// The kernels, once per SIMD target (Highway).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "cholesky/supernode_solve_kernel.cc"
#include <hwy/foreach_target.h>
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace warpchol::cholesky::HWY_NAMESPACE
{
  namespace hn = hwy::HWY_NAMESPACE;

  namespace
  {
    using DoubleTag = hn::ScalableTag<double>;
    using Doubles   = hn::Vec<DoubleTag>;

    /**
     * Columns per block: each row vector below the block is read and written once for all
     * of them (forward), or read once for all of their sums (backward).
     */
    constexpr int block_columns = 8;

    /** Where the B columns of block j0 of a supernode of nr rows start. */
    template <int B>
    void find_columns(const double *l, const Index nr, const Index j0, const double *(&column)[B])
    {
      for (int k = 0; k < B; ++k)
        column[k] = l + (j0 + k) * nr;
    }

    /**
     * Block j0 of B columns, forward: x[j0, j0 + B) solved with the block's diagonal, then
     * the rows below it (those of the supernode's later blocks and below it) updated.
     */
    template <int B>
    void forward_block(const double *l, const Index nr, const Index j0, double *work)
    {
      const DoubleTag d;
      const Index     lanes = static_cast<Index>(hn::Lanes(d));
      const double   *column[B];
      double          t[B];
      find_columns<B>(l, nr, j0, column);
      for (int k = 0; k < B; ++k)
        {
          t[k] = work[j0 + k] / column[k][j0 + k];
          for (int i = k + 1; i < B; ++i)
            work[j0 + i] -= column[k][j0 + i] * t[k];
        }
      Doubles factor[B];
      for (int k = 0; k < B; ++k)
        factor[k] = hn::Set(d, t[k]);
      Index i = j0 + B;
      for (; i + lanes <= nr; i += lanes)
        {
          Doubles y = hn::LoadU(d, work + i);
          for (int k = 0; k < B; ++k)
            y = hn::NegMulAdd(hn::LoadU(d, column[k] + i), factor[k], y);
          hn::StoreU(y, d, work + i);
        }
      for (; i < nr; ++i)
        {
          double y = work[i];
          for (int k = 0; k < B; ++k)
            y -= column[k][i] * t[k];
          work[i] = y;
        }
      for (int k = 0; k < B; ++k)
        work[j0 + k] = t[k];
    }

    /** Block j0 of B columns, backward: the rows after it already solved. */
    template <int B>
    void backward_block(const double *l, const Index nr, const Index j0, double *work)
    {
      const DoubleTag d;
      const Index     lanes = static_cast<Index>(hn::Lanes(d));
      const double   *column[B];
      Doubles         sum[B];
      find_columns<B>(l, nr, j0, column);
      for (int k = 0; k < B; ++k)
        sum[k] = hn::Zero(d);
      Index i = j0 + B;
      for (; i + lanes <= nr; i += lanes)
        {
          const Doubles x = hn::LoadU(d, work + i);
          for (int k = 0; k < B; ++k)
            sum[k] = hn::MulAdd(hn::LoadU(d, column[k] + i), x, sum[k]);
        }
      double rest[B] = {};
      for (; i < nr; ++i)
        for (int k = 0; k < B; ++k)
          rest[k] += column[k][i] * work[i];
      for (int k = B - 1; k >= 0; --k)
        {
          const Index j = j0 + k;
          double      v = work[j] - (hn::GetLane(hn::SumOfLanes(d, sum[k])) + rest[k]);
          for (int r = k + 1; r < B; ++r)
            v -= column[k][j0 + r] * work[j0 + r];
          work[j] = v / column[k][j];
        }
    }

    /** forward_block<count>() or backward_block<count>() for a last block of @p count (< block_columns) columns. */
    template <bool forward, int B>
    void last_block(const Index count, const double *l, const Index nr, const Index j0, double *work)
    {
      if constexpr (B > 1)
        if (count < B)
          return last_block<forward, B - 1>(count, l, nr, j0, work);
      if constexpr (forward)
        forward_block<B>(l, nr, j0, work);
      else
        backward_block<B>(l, nr, j0, work);
    }
  } // namespace

  void ForwardSupernodeDouble(const double *l, const Index nr, const Index nc, double *work)
  {
    Index j0 = 0;
    for (; j0 + block_columns <= nc; j0 += block_columns)
      forward_block<block_columns>(l, nr, j0, work);
    if (j0 < nc)
      last_block<true, block_columns - 1>(nc - j0, l, nr, j0, work);
  }

  void BackwardSupernodeDouble(const double *l, const Index nr, const Index nc, double *work)
  {
    // The forward pass's blocks, from the last.
    const Index whole = nc / block_columns * block_columns;
    if (whole < nc)
      last_block<false, block_columns - 1>(nc - whole, l, nr, whole, work);
    for (Index j0 = whole - block_columns; j0 >= 0; j0 -= block_columns)
      backward_block<block_columns>(l, nr, j0, work);
  }
} // namespace warpchol::cholesky::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace warpchol::cholesky
{
  HWY_EXPORT(ForwardSupernodeDouble);
  HWY_EXPORT(BackwardSupernodeDouble);

  void forward_supernode_double(const double *l, const Index nr, const Index nc, double *work)
  {
    HWY_DYNAMIC_DISPATCH(ForwardSupernodeDouble)(l, nr, nc, work);
  }

  void backward_supernode_double(const double *l, const Index nr, const Index nc, double *work)
  {
    HWY_DYNAMIC_DISPATCH(BackwardSupernodeDouble)(l, nr, nc, work);
  }

  void forward_supernode_gathered(const SupernodalSymbolic &symbolic, const double *values, const Index s, double *x,
                                  std::vector<double> &work)
  {
    const Index f = symbolic.first_column[s], nc = symbolic.n_columns(s), nr = symbolic.n_rows(s);
    work.resize(std::max<std::size_t>(work.size(), static_cast<std::size_t>(nr)));
    std::copy(x + f, x + f + nc, work.begin());
    std::fill(work.begin() + nc, work.begin() + nr, 0.);
    forward_supernode_double(values + symbolic.value_start[s], nr, nc, work.data());
    std::copy(work.begin(), work.begin() + nc, x + f);
  }
} // namespace warpchol::cholesky
#endif
