// arc_split, Highway version. Contract: kernels/arc_split.h (exact Gaussian-integer turn test,
// inflection before turning, split emission order and dedup as in the reference).
//
// Layout: the vertex lists of all curves are one array, so the pair tests run over the whole
// array at once, N consecutive pair starts p per vector, regardless of curve boundaries. A lane
// whose four vertices v[p-1 .. p+2] are not all in one curve (p within 2 before to 0 after a
// curve boundary) computes garbage (vector integer arithmetic wraps, nothing traps) and is
// masked out of the emission bits. Emission walks the set bits (inflection or turning) in
// increasing p, closing curves as it passes their last pair start, picks the split index as the
// reference does and applies its dedup (against the curve's previous split), without branches.
//
// Arithmetic, lane by lane the reference's:
//   z_k (int32 lanes): |a.b|, |a x b| <= 2 * 32766^2 < 2^31 for any coordinates |c| < 2^14
//     (<= 2^21 under the 1024 segment bound), so 32 bits are exact.
//   w = z_{k+1} conj(z_k) and the turned-more test (int64 lanes): int32 x int32 products by
//     MulEven, once for the even lanes and once for the odd lanes moved down by Shuffle2301; the
//     masks are merged back into int32 lanes with OddEven.
//   tan_q16 * Re w: a 64 x 64-bit product modulo 2^64 (Highway 1.0 has no int64 multiply on x86)
//     from 32-bit pieces: lo*lo (MulEven, unsigned) + ((lo*hi + hi*lo) mod 2^32) << 32 - the same
//     bits as the reference's int64 multiply; 65536 |Im w| is a shift by 16.
// The last pair starts, where a full vector would read past the vertex array, and every pair
// on HWY_SCALAR (one lane: no odd lane to pair) use the reference arithmetic per pair.
//
// Speed: on the detector's curves (about 6 polyline vertices per curve, so a third of the lanes
// straddle curves, and most of the time goes to gathering vertex coordinates and emitting splits)
// this is slower than the scalar reference on the development machine (AMD EPYC, AVX3: about
// 1.1-1.2x the reference's time, bench kernel/arc_split/*), so the SIMD kernel tables keep the
// reference (cpu/targets.cc); this version is conformance-tested and benchmarked directly.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "cpu/arc_split.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "cpu/simd_kernels.h"
#include "kernels/arc_split.h"

HWY_BEFORE_NAMESPACE();
namespace ellipsekit {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The reference decision for pair start p (global vertex position): the split index or -1.
HWY_INLINE std::int32_t SplitAtScalar(const std::int32_t* x, const std::int32_t* y, const std::int32_t* v,
                                      std::int32_t p, std::int64_t tan_q16) {
  struct Turn {
    std::int64_t re, im;
  };
  auto turn_at = [&](std::int32_t p0, std::int32_t p1, std::int32_t p2) {
    const std::int64_t ax = x[p1] - x[p0], ay = y[p1] - y[p0];
    const std::int64_t bx = x[p2] - x[p1], by = y[p2] - y[p1];
    return Turn{ax * bx + ay * by, ax * by - ay * bx};
  };
  auto sign = [](std::int64_t s) { return (s > 0) - (s < 0); };
  const Turn z0 = turn_at(v[p - 1], v[p], v[p + 1]);
  const Turn z1 = turn_at(v[p], v[p + 1], v[p + 2]);
  if (sign(z0.im) * sign(z1.im) < 0) return v[p] + (v[p + 1] - v[p]) / 2;
  const std::int64_t wre = z1.re * z0.re + z1.im * z0.im;
  const std::int64_t wim = z1.im * z0.re - z1.re * z0.im;
  if (wre <= 0 || 65536 * std::llabs(wim) > tan_q16 * wre) {
    const bool second_turns_more = z0.re * std::llabs(z1.im) - std::llabs(z0.im) * z1.re > 0;
    return second_turns_more ? v[p + 1] : v[p];
  }
  return -1;
}

// Writes splits in pair-start order, closing curves (offset entries) on the way. out->index is
// sized to the bound m (at most one split per pair start; no allocation once the capacity has
// been reached on an earlier frame) and written without branches; Finish() trims it.
struct Emitter {
  const Polylines& pl;
  Splits* out;
  int curves;
  std::int32_t* index = nullptr;
  std::int32_t count = 0;  // splits written
  std::int32_t last = -1;  // the open curve's last split (-1: none; splits are >= 0)
  int c = 0;               // the open curve

  Emitter(const Polylines& polylines, Splits* splits, int num_curves, std::int32_t bound)
      : pl(polylines), out(splits), curves(num_curves) {
    out->index.resize(static_cast<std::size_t>(bound));
    index = out->index.data();
  }
  // Whether pair start p (increasing from call to call) is an interior pair of a curve; closes
  // every curve whose last pair start (offset[c + 1] - 3) lies before p.
  bool Valid(std::int32_t p) {
    while (c < curves && p > pl.offset[c + 1] - 3) Close();
    return c < curves && p >= pl.offset[c] + 1;
  }
  // p: a valid pair start, increasing from call to call; split >= 0. The reference's dedup: a
  // split equal to the curve's previous one is dropped (written, then not counted).
  void Split(std::int32_t p, std::int32_t split) {
    if (!Valid(p)) return;
    index[count] = split;
    count += split != last;
    last = split;
  }
  void Close() {
    out->offset.push_back(count);
    ++c;
    last = -1;
  }
  void Finish() {
    while (c < curves) Close();
    out->index.resize(static_cast<std::size_t>(count));
  }
};

// 64 x 64 -> low 64 bits, from 32-bit pieces (see the header comment).
template <class D64>
HWY_INLINE hn::Vec<D64> MulLow64(D64 d64, hn::Vec<D64> a, hn::Vec<D64> b_lo32, hn::Vec<D64> b_hi32) {
  const hn::RebindToUnsigned<D64> du64;
  const hn::Repartition<std::uint32_t, D64> du32;
  const auto au = hn::BitCast(du64, a);
  const auto a_lo = hn::BitCast(du32, au);
  const auto a_hi = hn::BitCast(du32, hn::ShiftRight<32>(au));
  const auto lo = hn::MulEven(a_lo, hn::BitCast(du32, b_lo32));
  const auto cross = hn::Add(hn::Mul(a_lo, hn::BitCast(du32, b_hi32)), hn::Mul(a_hi, hn::BitCast(du32, b_lo32)));
  // The even 32-bit lane of each pair holds the cross term; the shift drops the odd one.
  const auto hi = hn::ShiftLeft<32>(hn::BitCast(du64, cross));
  return hn::BitCast(d64, hn::Add(lo, hi));
}

// The turning test and the turned-more choice for the pairs in the even 32-bit lanes of the
// inputs; both masks in int64 lanes.
template <class D32, class D64>
HWY_INLINE void EvenLaneTests(D32 /*d32*/, D64 d64, hn::Vec<D32> z0re, hn::Vec<D32> z0im, hn::Vec<D32> z1re,
                              hn::Vec<D32> z1im, hn::Vec<D64> tan_lo, hn::Vec<D64> tan_hi, hn::Mask<D64>* turning,
                              hn::Mask<D64>* second_more) {
  const auto zero = hn::Zero(d64);
  const auto wre = hn::Add(hn::MulEven(z1re, z0re), hn::MulEven(z1im, z0im));
  const auto wim = hn::Sub(hn::MulEven(z1im, z0re), hn::MulEven(z1re, z0im));
  const auto lhs = hn::ShiftLeft<16>(hn::Abs(wim));
  const auto rhs = MulLow64(d64, wre, tan_lo, tan_hi);
  *turning = hn::Or(hn::Not(hn::Gt(wre, zero)), hn::Gt(lhs, rhs));
  const auto more = hn::Sub(hn::MulEven(z0re, hn::Abs(z1im)), hn::MulEven(hn::Abs(z0im), z1re));
  *second_more = hn::Gt(more, zero);
}

void ArcSplitImpl(const Curves& curves, const Polylines& polylines, std::int64_t tan_q16, Splits* out) {
  out->clear();
  const hn::ScalableTag<std::int32_t> d;
  const hn::Repartition<std::int64_t, decltype(d)> d64;
  const std::int32_t n = static_cast<std::int32_t>(hn::Lanes(d));
  const std::int32_t* x = curves.x.data();
  const std::int32_t* y = curves.y.data();
  const std::int32_t* v = polylines.vertex.data();
  const std::int32_t m = static_cast<std::int32_t>(polylines.vertex.size());
  Emitter emit(polylines, out, curves.size(), std::max<std::int32_t>(m, 0));

  const std::uint64_t tan_bits = static_cast<std::uint64_t>(tan_q16);
  const auto tan_lo = hn::Set(d64, static_cast<std::int64_t>(tan_bits & 0xFFFFFFFFu));
  const auto tan_hi = hn::Set(d64, static_cast<std::int64_t>(tan_bits >> 32));
  const auto zero = hn::Zero(d);

  // Pair starts p = 1 .. m - 3 (the loads reach v[p + 2]).
  std::int32_t p = 1;
#if HWY_TARGET != HWY_SCALAR  // one lane has no odd lane to pair: the per-pair loop below does all
  // A block's n + 3 vertex coordinates are gathered once by scalar loads into a stack buffer,
  // and the four shifted windows are plain vector loads (vector gathers would fetch each vertex
  // four times and were slower). Two buffers: block b + 1 is gathered while block b computes,
  // so a window load never waits for the scalar stores just made to its own buffer.
  constexpr std::size_t kBuf = hn::MaxLanes(d) + 3;
  std::int32_t bx_buf[2][kBuf], by_buf[2][kBuf];
  auto gather = [&](std::int32_t at, int b) {
    for (std::int32_t l = 0; l < n + 3; ++l) {
      const std::int32_t idx = v[at - 1 + l];
      bx_buf[b][l] = x[idx];
      by_buf[b][l] = y[idx];
    }
  };
  // Pair starts that straddle two curves, q in [b - 2, b] for a curve boundary b = offset[c]:
  // their lanes compute garbage and are dropped from the emission bits (which also spares the
  // branches of emitting them). next_boundary: the first boundary not wholly before the block.
  const std::int32_t* bounds = polylines.offset.data();
  const int num_bounds = static_cast<int>(polylines.offset.size());
  int next_boundary = 1;
  auto straddling_bits = [&](std::int32_t block) {
    while (next_boundary < num_bounds && bounds[next_boundary] < block) ++next_boundary;
    std::uint64_t bits = 0;
    for (int b = next_boundary; b < num_bounds && bounds[b] - 2 < block + n; ++b) {
      const std::int32_t lo = std::max(bounds[b] - 2, block) - block, hi = std::min(bounds[b], block + n - 1) - block;
      bits |= ((std::uint64_t{2} << (hi - lo)) - 1) << lo;
    }
    return bits;
  };
  int cur = 0;
  if (p + n + 2 <= m) gather(p, cur);
  for (; p + n + 2 <= m; p += n, cur ^= 1) {
    const std::int32_t* vx = bx_buf[cur];
    const std::int32_t* vy = by_buf[cur];
    const auto x0 = hn::LoadU(d, vx), x1 = hn::LoadU(d, vx + 1), x2 = hn::LoadU(d, vx + 2), x3 = hn::LoadU(d, vx + 3);
    const auto y0 = hn::LoadU(d, vy), y1 = hn::LoadU(d, vy + 1), y2 = hn::LoadU(d, vy + 2), y3 = hn::LoadU(d, vy + 3);
    if (p + 2 * n + 2 <= m) gather(p + n, cur ^ 1);
    const auto ax = hn::Sub(x1, x0), ay = hn::Sub(y1, y0);
    const auto bx = hn::Sub(x2, x1), by = hn::Sub(y2, y1);
    const auto cx = hn::Sub(x3, x2), cy = hn::Sub(y3, y2);
    const auto z0re = hn::Add(hn::Mul(ax, bx), hn::Mul(ay, by));
    const auto z0im = hn::Sub(hn::Mul(ax, by), hn::Mul(ay, bx));
    const auto z1re = hn::Add(hn::Mul(bx, cx), hn::Mul(by, cy));
    const auto z1im = hn::Sub(hn::Mul(bx, cy), hn::Mul(by, cx));

    const auto inflection = hn::Or(hn::And(hn::Gt(z0im, zero), hn::Lt(z1im, zero)),
                                   hn::And(hn::Lt(z0im, zero), hn::Gt(z1im, zero)));
    hn::Mask<decltype(d64)> turn_even, more_even, turn_odd, more_odd;
    EvenLaneTests(d, d64, z0re, z0im, z1re, z1im, tan_lo, tan_hi, &turn_even, &more_even);
    EvenLaneTests(d, d64, hn::Shuffle2301(z0re), hn::Shuffle2301(z0im), hn::Shuffle2301(z1re),
                  hn::Shuffle2301(z1im), tan_lo, tan_hi, &turn_odd, &more_odd);
    // A 64-bit mask lane is all ones or all zeros, so either 32-bit half carries it.
    const auto turning = hn::MaskFromVec(hn::OddEven(hn::BitCast(d, hn::VecFromMask(d64, turn_odd)),
                                                     hn::BitCast(d, hn::VecFromMask(d64, turn_even))));
    const auto second_more = hn::MaskFromVec(hn::OddEven(hn::BitCast(d, hn::VecFromMask(d64, more_odd)),
                                                         hn::BitCast(d, hn::VecFromMask(d64, more_even))));
    // Emission from the lane bits (lane l = bit l): inflection before turning, as the reference.
    std::uint64_t infl_bits = 0, turn_bits = 0, more_bits = 0;
    hn::StoreMaskBits(d, inflection, reinterpret_cast<std::uint8_t*>(&infl_bits));
    hn::StoreMaskBits(d, turning, reinterpret_cast<std::uint8_t*>(&turn_bits));
    std::uint64_t any = (infl_bits | turn_bits) & ~straddling_bits(p);
    if (any != 0) hn::StoreMaskBits(d, second_more, reinterpret_cast<std::uint8_t*>(&more_bits));
    for (; any != 0; any &= any - 1) {
      const int l = hwy::Num0BitsBelowLS1Bit_Nonzero64(any);
      const std::int32_t q = p + l;
      const std::int32_t v0 = v[q], v1 = v[q + 1];
      const std::int32_t turned = ((more_bits >> l) & 1) ? v1 : v0;
      emit.Split(q, ((infl_bits >> l) & 1) ? v0 + (v1 - v0) / 2 : turned);
    }
  }
#else
  (void)n; (void)tan_lo; (void)tan_hi; (void)zero;
#endif
  for (; p + 2 < m; ++p) {
    if (!emit.Valid(p)) continue;
    const std::int32_t split = SplitAtScalar(x, y, v, p, tan_q16);
    if (split >= 0) emit.Split(p, split);
  }
  emit.Finish();
}

}  // namespace HWY_NAMESPACE
}  // namespace ellipsekit
HWY_AFTER_NAMESPACE();
