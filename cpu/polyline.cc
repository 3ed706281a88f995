// polyline, Highway version. Contract: kernels/polyline.h (exact Ramer-Douglas-Peucker, first
// farthest point on ties, halving of segments longer than kMaxSegmentComponent).
//
// The recursion (an explicit stack of chords) is the reference's own (PolylineWith); only the search
// for the farthest point of a chord (i, j) is vectorised, N interior points at a time in int32
// lanes. 32 bits are enough: with every coordinate |c| < 2^14 (kMaxImageDimension) each
// difference is at most 2^15 - 2 = 32766 in magnitude, each product at most 32766^2 < 2^30, and
// |cx dy - cy dx| <= 2 * 32766^2 = 2147221512 < 2^31 - 1, so neither the cross product nor its
// absolute value can overflow. The squared comparison after the search stays in int64 as in the
// reference.
// Tie rule: every lane keeps the first index at which its running maximum was strictly exceeded,
// so it holds the smallest index of its own maximum; the chord's farthest point is then the
// smallest index among the lanes that reach the overall maximum - the reference's first k.
// A chord with fewer interior points than one vector is searched by the reference loop (the
// vector set-up and the two cross-lane reductions would cost more). A longer chord's last partial
// vector is loaded in full and masked, as long as the load stays inside the point arrays (the
// extra lanes read other points and are discarded); otherwise the remaining points are searched
// by the reference loop and merged after the lanes (their indices are larger, so lanes win ties).
// Width: at most 8 lanes. RDP splits most chords down to a few dozen points, where 16-lane AVX3
// vectors lose more to the cutoff and the reductions than they gain (bench kernel/polyline/*:
// with 16 lanes AVX3 was slower than AVX2 on the same run; capped, the two are level).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "cpu/polyline.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "cpu/simd_kernels.h"
#include "kernels/polyline.h"

HWY_BEFORE_NAMESPACE();
namespace ellipsekit {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The farthest interior point of chord (i, j), j - i >= 2: the first k in (i, j) maximising
// |cross(p_j - p_i, p_k - p_i)|; *best_out receives that |cross|. `size` is the number of points
// in px / py (loads never reach past it).
HWY_INLINE std::int32_t FarthestPoint(const std::int32_t* HWY_RESTRICT px, const std::int32_t* HWY_RESTRICT py,
                                      std::int32_t size, std::int32_t i, std::int32_t j, std::int64_t* best_out) {
  const hn::CappedTag<std::int32_t, 8> d;  // see the header comment on the width
  const std::int32_t n = static_cast<std::int32_t>(hn::Lanes(d));
  const std::int32_t cx = px[j] - px[i], cy = py[j] - py[i];
  if (j - i - 1 < n) {  // fewer points than one vector: the reduction would cost more than the loop
    return FarthestPointInRange(px, py, i, j, i + 1, j, best_out);
  }
  const auto cxv = hn::Set(d, cx), cyv = hn::Set(d, cy);
  const auto xi = hn::Set(d, px[i]), yi = hn::Set(d, py[i]);
  auto best = hn::Set(d, -1);
  auto best_k = hn::Zero(d);
  auto kv = hn::Iota(d, i + 1);
  const auto step = hn::Set(d, n);
  std::int32_t k = i + 1;
  for (; k + n <= j; k += n) {
    const auto dy = hn::Sub(hn::LoadU(d, py + k), yi);
    const auto dx = hn::Sub(hn::LoadU(d, px + k), xi);
    const auto cr = hn::Abs(hn::Sub(hn::Mul(cxv, dy), hn::Mul(cyv, dx)));
    const auto better = hn::Gt(cr, best);  // strict: a lane keeps its first maximum
    best = hn::IfThenElse(better, cr, best);
    best_k = hn::IfThenElse(better, kv, best_k);
    kv = hn::Add(kv, step);
  }
  std::int64_t tail_best = -1;
  std::int32_t tail_k = -1;
  if (k < j) {
    if (k + n <= size) {
      const auto valid = hn::FirstN(d, static_cast<std::size_t>(j - k));
      const auto dy = hn::Sub(hn::LoadU(d, py + k), yi);
      const auto dx = hn::Sub(hn::LoadU(d, px + k), xi);
      const auto cr = hn::IfThenElse(valid, hn::Abs(hn::Sub(hn::Mul(cxv, dy), hn::Mul(cyv, dx))), hn::Set(d, -1));
      const auto better = hn::Gt(cr, best);
      best = hn::IfThenElse(better, cr, best);
      best_k = hn::IfThenElse(better, kv, best_k);
    } else {
      tail_k = FarthestPointInRange(px, py, i, j, k, j, &tail_best);
    }
  }
  const std::int32_t vmax = hn::GetLane(hn::MaxOfLanes(d, best));
  std::int32_t vk = -1;
  if (vmax >= 0) {
    const auto candidates =
        hn::IfThenElse(hn::Eq(best, hn::Set(d, vmax)), best_k, hn::Set(d, std::numeric_limits<std::int32_t>::max()));
    vk = hn::GetLane(hn::MinOfLanes(d, candidates));
  }
  // The vector lanes cover smaller indices than the scalar tail: they win ties.
  if (tail_best > vmax) {
    *best_out = tail_best;
    return tail_k;
  }
  *best_out = vmax;
  return vk;
}

void PolylineImpl(const Curves& curves, std::int32_t tol_q16, Polylines* out, std::vector<std::int32_t>* stack) {
  const std::int32_t* px = curves.x.data();
  const std::int32_t* py = curves.y.data();
  const std::int32_t size = static_cast<std::int32_t>(curves.x.size());
  auto farthest = [px, py, size](std::int32_t i, std::int32_t j, std::int64_t* best) HWY_ATTR {
    return FarthestPoint(px, py, size, i, j, best);
  };
  PolylineWith(curves, tol_q16, out, stack, farthest);
}

}  // namespace HWY_NAMESPACE
}  // namespace ellipsekit
HWY_AFTER_NAMESPACE();
