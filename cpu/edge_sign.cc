// edge_sign, Highway version. Contract: kernels/edge_sign.h (paper eq. 1, exact).
//
// sign(dx * dy) needs no multiply: the product is > 0 when both are non-zero with the same sign
// and < 0 when both are non-zero with opposite signs, i.e. when (dx ^ dy) < 0. Lanes are int16
// (the gradients' type); the edge bytes are widened to int16 and the class narrowed back.
// `out` may alias `edges`: each vector's edge bytes are loaded before its class is stored.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "cpu/edge_sign.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <cstddef>
#include <cstdint>

#include "cpu/simd_kernels.h"
#include "kernels/edge_sign.h"

HWY_BEFORE_NAMESPACE();
namespace ellipsekit {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void EdgeSignImpl(const std::uint8_t* edges, std::ptrdiff_t edge_stride, const std::int16_t* dx,
                  const std::int16_t* dy, std::ptrdiff_t stride, int width, int height,
                  std::uint8_t* out, std::ptrdiff_t out_stride) {
  const hn::ScalableTag<std::int16_t> d16;
  const hn::Rebind<std::uint8_t, decltype(d16)> d8;
  const int n = static_cast<int>(hn::Lanes(d16));
  const auto zero = hn::Zero(d16);
  const auto plus = hn::Set(d16, kEdgePlus);
  const auto minus = hn::Set(d16, kEdgeMinus);
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* e = edges + y * edge_stride;
    const std::int16_t* gx = dx + y * stride;
    const std::int16_t* gy = dy + y * stride;
    std::uint8_t* o = out + y * out_stride;
    int x = 0;
    for (; x + n <= width; x += n) {
      const auto ev = hn::PromoteTo(d16, hn::LoadU(d8, e + x));
      const auto gxv = hn::LoadU(d16, gx + x);
      const auto gyv = hn::LoadU(d16, gy + x);
      const auto keep = hn::And(hn::Ne(ev, zero), hn::And(hn::Ne(gxv, zero), hn::Ne(gyv, zero)));
      const auto cls = hn::IfThenElse(hn::Lt(hn::Xor(gxv, gyv), zero), minus, plus);
      hn::StoreU(hn::DemoteTo(d8, hn::IfThenElseZero(keep, cls)), d8, o + x);
    }
    for (; x < width; ++x) {
      const std::int32_t p = static_cast<std::int32_t>(gx[x]) * gy[x];
      o[x] = e[x] == 0 ? kEdgeNone : p > 0 ? kEdgePlus : p < 0 ? kEdgeMinus : kEdgeNone;
    }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace ellipsekit
HWY_AFTER_NAMESPACE();
