// nms, Highway version. Contract: kernels/nms.h (fixed-point direction test, thresholds, border
// rows and columns 0, exact).
//
// Interior pixels x in [1, width - 2] of rows 1..height-2 go N at a time in int16 lanes (mag <=
// 2040 and |dx|, |dy| <= 1020 from the Sobel; the domain kernels/nms.h states). The direction test
// compares (|dy| << 15) with 13573 |dx| and 79109 |dx|, which need 32 bits; each is compared as a
// (high, low) pair of 16-bit halves: ay << 15 = (ay >> 1, (ay & 1) << 15); 13573 ax = (MulHigh,
// Mul) of ax and 13573; 79109 ax = 65536 ax + 13573 ax = (ax + that high half, the same low half).
// The low halves compare unsigned (sign bits flipped, then a signed compare). All three candidate
// neighbour pairs are loaded and the pair is chosen per lane with masks, so each lane makes
// exactly the reference's comparisons:
//   horizontal: m >  mag(x-1, y)   and m >= mag(x+1, y)
//   vertical:   m >  mag(x, y-1)   and m >= mag(x, y+1)
//   diagonal:   m >  mag(x-s, y-1) and m >  mag(x+s, y+1),  s = +1 when dx, dy share a sign.
// Each tile's columns (kernels/nms.h NmsThresholds) go as one run with that tile's thresholds;
// a run's tail shorter than a vector goes pixel by pixel through the reference's own rule
// (kernels/nms.h NmsPixel).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "cpu/nms.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "cpu/simd_kernels.h"
#include "kernels/nms.h"

HWY_BEFORE_NAMESPACE();
namespace ellipsekit {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// A threshold as an int16 lane: mag lies in [0, 32767], so clamping keeps every m > t the same.
HWY_INLINE std::int16_t ClampToInt16(std::int32_t t) { return static_cast<std::int16_t>(std::clamp(t, -32768, 32767)); }

void NmsImpl(const std::int16_t* dx, const std::int16_t* dy, const std::uint16_t* mag, int width,
             int height, std::ptrdiff_t stride, const NmsThresholds& th, std::uint8_t* out,
             std::ptrdiff_t out_stride) {
  const hn::ScalableTag<std::int16_t> d16;
  const hn::RebindToUnsigned<decltype(d16)> du16;
  const hn::Rebind<std::uint8_t, decltype(d16)> du8;
  const int n = static_cast<int>(hn::Lanes(d16));
  auto load_mag = [&](const std::uint16_t* p) { return hn::BitCast(d16, hn::LoadU(du16, p)); };
  const auto tan22 = hn::Set(d16, static_cast<std::int16_t>(kTan22Q15));
  static_assert(kTan67Q15 == 65536 + kTan22Q15, "79109 ax = 65536 ax + 13573 ax");
  const auto one = hn::Set(d16, 1);
  const auto sign_bit = hn::Set(d16, static_cast<std::int16_t>(-32768));
  const auto zero = hn::Zero(d16);
  const auto weak = hn::Set(d16, kNmsWeak);
  const auto strong = hn::Set(d16, kNmsStrong);
  for (int y = 0; y < height; ++y) {
    std::uint8_t* o = out + y * out_stride;
    if (y == 0 || y == height - 1 || width < 3) {
      std::memset(o, 0, static_cast<std::size_t>(width));
      continue;
    }
    const std::uint16_t* mp = mag + (y - 1) * stride;
    const std::uint16_t* mc = mag + y * stride;
    const std::uint16_t* mn = mag + (y + 1) * stride;
    const std::int16_t* gx = dx + y * stride;
    const std::int16_t* gy = dy + y * stride;
    o[0] = kNmsNone;
    o[width - 1] = kNmsNone;
    const std::int32_t* low_row = th.low + (y >> th.shift) * th.tiles_x;
    const std::int32_t* high_row = th.high + (y >> th.shift) * th.tiles_x;
    for (int tile = 0, x = 1; x < width - 1; ++tile) {
      const int low = low_row[tile], high = high_row[tile];
      const auto low_v = hn::Set(d16, ClampToInt16(low));
      const auto high_v = hn::Set(d16, ClampToInt16(high));
      // This tile's columns up to end; the loads reach x + n, which stays <= end <= width - 1.
      const int end = static_cast<int>(std::min<std::int64_t>(width - 1, (std::int64_t{tile} + 1) << th.shift));
      for (; x + n <= end; x += n) {
        const auto m = load_mag(mc + x);
        const auto above_low = hn::Gt(m, low_v);
        if (hn::AllFalse(d16, above_low)) {  // most of a frame: no candidate in these lanes
          hn::StoreU(hn::Zero(du8), du8, o + x);
          continue;
        }
        const auto gxv = hn::LoadU(d16, gx + x);
        const auto gyv = hn::LoadU(d16, gy + x);
        const auto ax = hn::Abs(gxv), ay = hn::Abs(gyv);
        // ay << 15 as (high, low with its sign bit flipped); 13573 ax and 79109 ax alike.
        const auto a_hi = hn::ShiftRight<1>(ay);
        const auto a_lo = hn::Xor(hn::ShiftLeft<15>(hn::And(ay, one)), sign_bit);
        const auto t22_hi = hn::MulHigh(ax, tan22);
        const auto t_lo = hn::Xor(hn::Mul(ax, tan22), sign_bit);
        const auto t67_hi = hn::Add(ax, t22_hi);
        const auto horizontal = hn::Or(hn::Lt(a_hi, t22_hi), hn::And(hn::Eq(a_hi, t22_hi), hn::Lt(a_lo, t_lo)));
        const auto above_67 = hn::Or(hn::Gt(a_hi, t67_hi), hn::And(hn::Eq(a_hi, t67_hi), hn::Gt(a_lo, t_lo)));
        const auto vertical = hn::AndNot(horizontal, above_67);
        const auto diagonal = hn::Not(hn::Or(horizontal, vertical));
        // s = -1 (opposite signs): neighbours (x+1, y-1), (x-1, y+1); s = +1: (x-1, y-1), (x+1, y+1).
        const auto opposite = hn::Lt(hn::Xor(gxv, gyv), zero);

        const auto c_left = load_mag(mc + x - 1), c_right = load_mag(mc + x + 1);
        const auto p_left = load_mag(mp + x - 1), p_mid = load_mag(mp + x), p_right = load_mag(mp + x + 1);
        const auto n_left = load_mag(mn + x - 1), n_mid = load_mag(mn + x), n_right = load_mag(mn + x + 1);

        const auto diag_first = hn::IfThenElse(opposite, p_right, p_left);
        const auto diag_second = hn::IfThenElse(opposite, n_left, n_right);
        const auto first = hn::IfThenElse(horizontal, c_left, hn::IfThenElse(vertical, p_mid, diag_first));
        const auto second =
            hn::IfThenElse(horizontal, c_right, hn::IfThenElse(vertical, n_mid, diag_second));
        // Diagonal needs m > second; the other two directions m >= second.
        // (Highway 1.0 has no integer >= on x86, hence > or ==.)
        const auto second_ok = hn::Or(hn::Gt(m, second), hn::AndNot(diagonal, hn::Eq(m, second)));
        const auto is_edge = hn::And(hn::And(above_low, hn::Gt(m, first)), second_ok);
        const auto cls = hn::IfThenElseZero(is_edge, hn::IfThenElse(hn::Gt(m, high_v), strong, weak));
        hn::StoreU(hn::DemoteTo(du8, cls), du8, o + x);
      }
      for (; x < end; ++x) o[x] = NmsPixel(mp, mc, mn, gx, gy, x, low, high);
    }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace ellipsekit
HWY_AFTER_NAMESPACE();
