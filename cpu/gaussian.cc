// gaussian, Highway version. Contract: kernels/gaussian.h (3x3 binomial, replicate border, exact).
//
// The interior columns x in [1, width - 2] are computed N at a time in int16 lanes: the column
// sums up + 2*mid + down are <= 1020 and the weighted row sum + 8 is <= 4088, so nothing wraps
// and (sum + 8) >> 4 is the reference's value. Column 0, column width - 1 (replicated
// neighbours) and the row tail shorter than a vector use the reference formula per pixel.
// Rows above/below the image are replicated by choosing the row pointers, as in the reference.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "cpu/gaussian.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "cpu/simd_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace ellipsekit {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// One output pixel exactly as kernels/gaussian.cc computes it.
HWY_INLINE std::uint8_t GaussianPixel(const std::uint8_t* up, const std::uint8_t* mid,
                                      const std::uint8_t* down, int x, int width) {
  const int xl = std::max(x - 1, 0), xr = std::min(x + 1, width - 1);
  const int left = up[xl] + 2 * mid[xl] + down[xl];
  const int centre = up[x] + 2 * mid[x] + down[x];
  const int right = up[xr] + 2 * mid[xr] + down[xr];
  return static_cast<std::uint8_t>((left + 2 * centre + right + 8) >> 4);
}

// up[x] + 2 * mid[x] + down[x] for N consecutive x, widened to int16.
template <class D16, class D8>
HWY_INLINE hn::Vec<D16> ColumnSum(D16 d16, D8 d8, const std::uint8_t* up, const std::uint8_t* mid,
                                  const std::uint8_t* down) {
  const auto u = hn::PromoteTo(d16, hn::LoadU(d8, up));
  const auto m = hn::PromoteTo(d16, hn::LoadU(d8, mid));
  const auto d = hn::PromoteTo(d16, hn::LoadU(d8, down));
  return hn::Add(hn::Add(u, d), hn::ShiftLeft<1>(m));
}

void GaussianImpl(const std::uint8_t* src, std::ptrdiff_t src_stride, int width, int height,
                  std::uint8_t* dst, std::ptrdiff_t dst_stride) {
  const hn::ScalableTag<std::int16_t> d16;
  const hn::Rebind<std::uint8_t, decltype(d16)> d8;
  const int n = static_cast<int>(hn::Lanes(d16));
  const auto round = hn::Set(d16, 8);
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* up = src + std::max(y - 1, 0) * src_stride;
    const std::uint8_t* mid = src + y * src_stride;
    const std::uint8_t* down = src + std::min(y + 1, height - 1) * src_stride;
    std::uint8_t* out = dst + y * dst_stride;
    out[0] = GaussianPixel(up, mid, down, 0, width);
    int x = 1;
    // The loads reach x + n, which must stay <= width - 1.
    for (; x + n <= width - 1; x += n) {
      const auto left = ColumnSum(d16, d8, up + x - 1, mid + x - 1, down + x - 1);
      const auto centre = ColumnSum(d16, d8, up + x, mid + x, down + x);
      const auto right = ColumnSum(d16, d8, up + x + 1, mid + x + 1, down + x + 1);
      const auto sum = hn::Add(hn::Add(left, right), hn::Add(hn::ShiftLeft<1>(centre), round));
      hn::StoreU(hn::DemoteTo(d8, hn::ShiftRight<4>(sum)), d8, out + x);
    }
    for (; x < width; ++x) out[x] = GaussianPixel(up, mid, down, x, width);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace ellipsekit
HWY_AFTER_NAMESPACE();
