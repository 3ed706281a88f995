// arc_stats, Highway version. Contract: kernels/arc_stats.h (exact integer statistics, arcs
// in curve order, arcs shorter than min_points skipped).
//
// Per arc, the reductions over its points run N at a time in int32 lanes:
//   min / max of x and y (exact in any order);
//   the bulge sums, rewritten as b = 2 sum_i p_i - n (first + last), which equals the reference's
//     sum_i (2 p_i - (first + last)) as an integer. sum_i x_i is accumulated in int32 lanes over
//     chunks of at most kChunk = 2^16 points (every lane total and the chunk total stay below
//     2^16 * 2^14 = 2^30) and carried in int64 between chunks, so nothing overflows.
// An arc's last partial vector is loaded in full and the lanes outside the arc are masked out
// (neutral: the first point for min / max, 0 for sums); the load ends at the arc's last point,
// or where that would start before the arrays, begins at the arc's next point; if neither fits
// (fewer points in the whole curve set than one vector) the reference loop takes them.
// The end gradient sums cover k = clamp(n / 4, 1, 4) points: one 4-lane int32 vector per end
// and component (int16 gradients promoted), masked to k lanes, where the 4-point load stays in
// the arrays; otherwise the reference loop.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "cpu/arc_stats.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "cpu/simd_kernels.h"
#include "kernels/arc_stats.h"

HWY_BEFORE_NAMESPACE();
namespace ellipsekit {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

constexpr std::int32_t kChunk = 1 << 16;

// Running reductions of one arc in int32 lanes.
template <class D>
struct Reduction {
  hn::Vec<D> min_x, max_x, min_y, max_y, sum_x, sum_y;
};

template <class D>
HWY_INLINE void Accumulate(hn::Vec<D> xv, hn::Vec<D> yv, Reduction<D>* r) {
  r->min_x = hn::Min(r->min_x, xv); r->max_x = hn::Max(r->max_x, xv);
  r->min_y = hn::Min(r->min_y, yv); r->max_y = hn::Max(r->max_y, yv);
  r->sum_x = hn::Add(r->sum_x, xv); r->sum_y = hn::Add(r->sum_y, yv);
}

// Lanes outside `valid` become neutral: the arc's first point for min / max, zero for the sums.
template <class D>
HWY_INLINE void AccumulateMasked(hn::Mask<D> valid, hn::Vec<D> xv, hn::Vec<D> yv, hn::Vec<D> x0,
                                 hn::Vec<D> y0, Reduction<D>* r) {
  r->min_x = hn::Min(r->min_x, hn::IfThenElse(valid, xv, x0));
  r->max_x = hn::Max(r->max_x, hn::IfThenElse(valid, xv, x0));
  r->min_y = hn::Min(r->min_y, hn::IfThenElse(valid, yv, y0));
  r->max_y = hn::Max(r->max_y, hn::IfThenElse(valid, yv, y0));
  r->sum_x = hn::Add(r->sum_x, hn::IfThenElseZero(valid, xv));
  r->sum_y = hn::Add(r->sum_y, hn::IfThenElseZero(valid, yv));
}

// Lane masks for the 4-lane gradient sums: kKeepMask + 4 - k keeps the first k lanes,
// kDropMask + k keeps the last k. (A table rather than FirstN: GCC 12 fails with an internal
// error on the masked sign-extending load that FirstN + IfThenElseZero compiles to on AVX3.)
constexpr std::int32_t kKeepMask[8] = {-1, -1, -1, -1, 0, 0, 0, 0};
constexpr std::int32_t kDropMask[8] = {0, 0, 0, 0, -1, -1, -1, -1};

// Sum of the first k (1..4) int16 values at p, or (backward) of the k values ending at p.
// load_ok: the 4-value load (p[0..3], or p[-3..0] backward) stays inside the array.
HWY_INLINE std::int32_t GradientSum(const std::int16_t* p, std::int32_t k, bool backward, bool load_ok) {
  const hn::CappedTag<std::int32_t, 4> d4;
  const hn::Rebind<std::int16_t, decltype(d4)> d16;
  if (!load_ok || hn::Lanes(d4) < 4) {  // HWY_SCALAR has one lane
    std::int32_t s = 0;
    for (std::int32_t i = 0; i < k; ++i) s += backward ? p[-i] : p[i];
    return s;
  }
  const auto v = hn::PromoteTo(d4, hn::LoadU(d16, backward ? p - 3 : p));
  const auto keep = hn::LoadU(d4, backward ? kDropMask + k : kKeepMask + 4 - k);
  return hn::GetLane(hn::SumOfLanes(d4, hn::And(v, keep)));
}

ArcStats MakeArc(const Curves& c, int curve, std::int32_t begin, std::int32_t end) {
  const hn::ScalableTag<std::int32_t> d;
  const std::int32_t n = static_cast<std::int32_t>(hn::Lanes(d));
  const std::int32_t size = static_cast<std::int32_t>(c.x.size());
  const std::int32_t* px = c.x.data();
  const std::int32_t* py = c.y.data();
  ArcStats a = ArcPointStats(c, curve, begin, end);

  const auto x0 = hn::Set(d, a.x0), y0 = hn::Set(d, a.y0);
  Reduction<decltype(d)> r{x0, x0, y0, y0, hn::Zero(d), hn::Zero(d)};
  std::int64_t sum_x = 0, sum_y = 0;
  auto flush = [&] {
    sum_x += hn::GetLane(hn::SumOfLanes(d, r.sum_x));
    sum_y += hn::GetLane(hn::SumOfLanes(d, r.sum_y));
    r.sum_x = hn::Zero(d);
    r.sum_y = hn::Zero(d);
  };
  std::int32_t i = begin;
  while (end + 1 - i >= n) {
    const std::int32_t chunk_end = i + std::min((end + 1 - i) / n, kChunk / n) * n;
    for (; i < chunk_end; i += n) Accumulate(hn::LoadU(d, px + i), hn::LoadU(d, py + i), &r);
    flush();
  }
  const std::int32_t rest = end + 1 - i;  // 0 .. n - 1 points
  if (rest > 0) {
    if (end + 1 >= n) {  // the vector ending at `end`; its first n - rest lanes are done or not ours
      const std::int32_t at = end + 1 - n;
      const auto valid = hn::Not(hn::FirstN(d, static_cast<std::size_t>(n - rest)));
      AccumulateMasked(valid, hn::LoadU(d, px + at), hn::LoadU(d, py + at), x0, y0, &r);
    } else if (i + n <= size) {  // the vector starting at i
      const auto valid = hn::FirstN(d, static_cast<std::size_t>(rest));
      AccumulateMasked(valid, hn::LoadU(d, px + i), hn::LoadU(d, py + i), x0, y0, &r);
    } else {
      for (; i <= end; ++i) {
        a.min_x = std::min(a.min_x, px[i]); a.max_x = std::max(a.max_x, px[i]);
        a.min_y = std::min(a.min_y, py[i]); a.max_y = std::max(a.max_y, py[i]);
        sum_x += px[i];
        sum_y += py[i];
      }
    }
    flush();
  }
  // The vector lanes start at the first point, so they are neutral if the reference loop ran.
  a.min_x = std::min(a.min_x, hn::GetLane(hn::MinOfLanes(d, r.min_x)));
  a.max_x = std::max(a.max_x, hn::GetLane(hn::MaxOfLanes(d, r.max_x)));
  a.min_y = std::min(a.min_y, hn::GetLane(hn::MinOfLanes(d, r.min_y)));
  a.max_y = std::max(a.max_y, hn::GetLane(hn::MaxOfLanes(d, r.max_y)));
  const std::int64_t points = end - begin + 1;
  const std::int64_t bx = 2 * sum_x - points * (static_cast<std::int64_t>(a.x0) + a.x1);
  const std::int64_t by = 2 * sum_y - points * (static_cast<std::int64_t>(a.y0) + a.y1);

  const std::int32_t k = std::clamp((end - begin + 1) / 4, 1, 4);
  a.g0x = GradientSum(c.gx.data() + begin, k, false, begin + 4 <= size);
  a.g0y = GradientSum(c.gy.data() + begin, k, false, begin + 4 <= size);
  a.g1x = GradientSum(c.gx.data() + end, k, true, end >= 3);
  a.g1y = GradientSum(c.gy.data() + end, k, true, end >= 3);
  a.quadrant = QuadrantFromBulge(a.sign_class, bx, by);
  return a;
}

void ArcStatsFromSplitsImpl(const Curves& curves, const Splits& splits, int min_points, std::vector<ArcStats>* out) {
  ArcStatsWith(curves, splits, min_points, out, [&curves](int c, std::int32_t begin, std::int32_t end) HWY_ATTR {
    return MakeArc(curves, c, begin, end);
  });
}

}  // namespace HWY_NAMESPACE
}  // namespace ellipsekit
HWY_AFTER_NAMESPACE();
