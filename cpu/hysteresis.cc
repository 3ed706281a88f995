// hysteresis, Highway version. Contract: kernels/hysteresis.h (order independent, exact).
//
// The flood is the reference's (HysteresisFlood: a pixel's 8 neighbours are scattered over three
// rows, which vectors do not help). What vectors do is the two passes over every pixel: finding
// the strong pixels a flood starts from, N bytes at a time (strong pixels are rare, so most
// vectors hold none), and the final relabel (mark -> 1, anything else -> 0). A vector's bytes are
// re-read one by one before a flood starts from them: an earlier flood of the same vector may
// have marked them already.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "cpu/hysteresis.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <cstddef>
#include <cstdint>

#include "cpu/simd_kernels.h"
#include "kernels/hysteresis.h"
#include "kernels/nms.h"

HWY_BEFORE_NAMESPACE();
namespace ellipsekit {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void HysteresisImpl(std::uint8_t* map, int width, int height, std::ptrdiff_t stride,
                    std::int32_t* stack) {
  const hn::ScalableTag<std::uint8_t> d8;
  const int n = static_cast<int>(hn::Lanes(d8));
  const auto strong = hn::Set(d8, kNmsStrong);
  for (int y = 0; y < height; ++y) {
    std::uint8_t* row = map + y * stride;
    int x = 0;
    for (; x + n <= width; x += n) {
      if (hn::AllFalse(d8, hn::Eq(hn::LoadU(d8, row + x), strong))) continue;
      for (int i = x; i < x + n; ++i) {
        if (row[i] == kNmsStrong) HysteresisFlood(map, width, height, stride, stack, i, y);
      }
    }
    for (; x < width; ++x) {
      if (row[x] == kNmsStrong) HysteresisFlood(map, width, height, stride, stack, x, y);
    }
  }
  const auto mark = hn::Set(d8, kHysteresisMark);
  const auto one = hn::Set(d8, 1);
  for (int y = 0; y < height; ++y) {
    std::uint8_t* row = map + y * stride;
    int x = 0;
    for (; x + n <= width; x += n) {
      hn::StoreU(hn::IfThenElseZero(hn::Eq(hn::LoadU(d8, row + x), mark), one), d8, row + x);
    }
    for (; x < width; ++x) row[x] = (row[x] == kHysteresisMark) ? 1 : 0;
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace ellipsekit
HWY_AFTER_NAMESPACE();
