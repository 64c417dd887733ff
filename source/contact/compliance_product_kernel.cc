#include "compliance_product_kernel.h"

#include <warpchol/base/simd.h>

// The kernel, once per SIMD target (Highway's foreach_target).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "contact/compliance_product_kernel.cc"
#include <hwy/foreach_target.h>
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace warpchol::fem::HWY_NAMESPACE
{
  namespace hn = hwy::HWY_NAMESPACE;

  void AddThreeColumns(const double *columns, const std::size_t length, const double *t, double *y)
  {
    const hn::ScalableTag<double> d;
    const std::size_t             lanes = hn::Lanes(d);
    const double *c0 = columns, *c1 = columns + length, *c2 = columns + 2 * length;
    const auto    t0 = hn::Set(d, t[0]), t1 = hn::Set(d, t[1]), t2 = hn::Set(d, t[2]);
    std::size_t   i = 0;
    for (; i + lanes <= length; i += lanes)
      {
        auto sum = hn::MulAdd(hn::LoadU(d, c0 + i), t0, hn::LoadU(d, y + i));
        sum      = hn::MulAdd(hn::LoadU(d, c1 + i), t1, sum);
        hn::StoreU(hn::MulAdd(hn::LoadU(d, c2 + i), t2, sum), d, y + i);
      }
    for (; i < length; ++i)
      y[i] += c0[i] * t[0] + c1[i] * t[1] + c2[i] * t[2];
  }
} // namespace warpchol::fem::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace warpchol::fem
{
  HWY_EXPORT(AddThreeColumns);

  void add_three_columns(const double *columns, const std::size_t length, const double (&t)[3], double *y)
  {
    simd::use_target_from_environment();
    HWY_DYNAMIC_DISPATCH(AddThreeColumns)(columns, length, t, y);
  }
} // namespace warpchol::fem
#endif
