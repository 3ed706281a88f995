// sobel, Highway version. Contract: kernels/sobel.h (3x3 Sobel dx, dy and |dx| + |dy|, replicate
// border, exact).
//
// Interior columns x in [1, width - 2] go N at a time in int16 lanes: |dx|, |dy| <= 1020 and
// mag <= 2040, so int16 arithmetic is exact and mag is stored through a bit cast to uint16.
// Column 0, column width - 1 and the row tail use the reference formula per pixel; rows outside
// the image are replicated by choosing the row pointers, as in the reference.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "cpu/sobel.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "cpu/simd_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace ellipsekit {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// One output pixel exactly as kernels/sobel.cc computes it.
HWY_INLINE void SobelPixel(const std::uint8_t* up, const std::uint8_t* mid, const std::uint8_t* down,
                           int x, int width, std::int16_t* dx, std::int16_t* dy,
                           std::uint16_t* mag) {
  const int xl = std::max(x - 1, 0), xr = std::min(x + 1, width - 1);
  const int gx = (up[xr] + 2 * mid[xr] + down[xr]) - (up[xl] + 2 * mid[xl] + down[xl]);
  const int gy = (down[xl] + 2 * down[x] + down[xr]) - (up[xl] + 2 * up[x] + up[xr]);
  dx[x] = static_cast<std::int16_t>(gx);
  dy[x] = static_cast<std::int16_t>(gy);
  mag[x] = static_cast<std::uint16_t>(std::abs(gx) + std::abs(gy));
}

template <class D16, class D8>
HWY_INLINE hn::Vec<D16> Load16(D16 d16, D8 d8, const std::uint8_t* p) {
  return hn::PromoteTo(d16, hn::LoadU(d8, p));
}

void SobelImpl(const std::uint8_t* src, std::ptrdiff_t src_stride, int width, int height,
               std::int16_t* dx, std::int16_t* dy, std::uint16_t* mag, std::ptrdiff_t stride) {
  const hn::ScalableTag<std::int16_t> d16;
  const hn::Rebind<std::uint8_t, decltype(d16)> d8;
  const hn::RebindToUnsigned<decltype(d16)> du16;
  const int n = static_cast<int>(hn::Lanes(d16));
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* up = src + std::max(y - 1, 0) * src_stride;
    const std::uint8_t* mid = src + y * src_stride;
    const std::uint8_t* down = src + std::min(y + 1, height - 1) * src_stride;
    std::int16_t* gx_row = dx + y * stride;
    std::int16_t* gy_row = dy + y * stride;
    std::uint16_t* mag_row = mag + y * stride;
    SobelPixel(up, mid, down, 0, width, gx_row, gy_row, mag_row);
    int x = 1;
    // The loads reach x + n, which must stay <= width - 1.
    for (; x + n <= width - 1; x += n) {
      const auto ul = Load16(d16, d8, up + x - 1), uc = Load16(d16, d8, up + x),
                 ur = Load16(d16, d8, up + x + 1);
      const auto ml = Load16(d16, d8, mid + x - 1), mr = Load16(d16, d8, mid + x + 1);
      const auto dl = Load16(d16, d8, down + x - 1), dc = Load16(d16, d8, down + x),
                 dr = Load16(d16, d8, down + x + 1);
      // dx = (ur + 2 mr + dr) - (ul + 2 ml + dl); dy = (dl + 2 dc + dr) - (ul + 2 uc + ur).
      const auto gx = hn::Add(hn::Sub(hn::Add(ur, dr), hn::Add(ul, dl)),
                              hn::ShiftLeft<1>(hn::Sub(mr, ml)));
      const auto gy = hn::Add(hn::Sub(hn::Add(dl, dr), hn::Add(ul, ur)),
                              hn::ShiftLeft<1>(hn::Sub(dc, uc)));
      hn::StoreU(gx, d16, gx_row + x);
      hn::StoreU(gy, d16, gy_row + x);
      hn::StoreU(hn::BitCast(du16, hn::Add(hn::Abs(gx), hn::Abs(gy))), du16, mag_row + x);
    }
    for (; x < width; ++x) SobelPixel(up, mid, down, x, width, gx_row, gy_row, mag_row);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace ellipsekit
HWY_AFTER_NAMESPACE();
