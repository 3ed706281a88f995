// arc_stats: the statistics of every arc that the fit back end needs (sec. II-B-2).
//
// For an arc [begin, end] of a curve (kernels/arc_types.h):
//   end points, middle point (index (begin + end) / 2), axis-aligned bounding box,
//   gradient sums over the first and last k = clamp(n / 4, 1, 4) points (the end tangents are
//   perpendicular to them), and the quadrant from convexity (eq. 2) and the gradient class (eq. 1).
// Convexity: the paper calls an arc convex when its middle point lies higher than the middle of
// its chord. One middle pixel is ill-conditioned (on short or flat arcs it often lies on the
// chord), so the bulge is summed over every point, b = sum_i (2 p_i - (first + last)) (int64;
// it is twice the arc's mean offset from its chord, times n), and read along the diagonal the
// quadrant's arcs bulge to:
//   class "-" (I upper-right or III lower-left):  b.x - b.y > 0 -> I,  < 0 -> III
//   class "+" (II upper-left or IV lower-right):  b.x + b.y < 0 -> II, > 0 -> IV
//   0 -> undecided (quadrant 0). Where the paper's test is well-conditioned both agree.
// Exact: integer only.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/arc_split.h"
#include "kernels/arc_types.h"

namespace ellipsekit {

namespace scalar {

// Appends one ArcStats per arc of every curve, in curve order. Arcs with fewer than
// min_points points are skipped (T_n, sec. II-B-1: "filtering ... used again").
void ArcStatsFromSplits(const Curves& curves, const Splits& splits, int min_points,
                        std::vector<ArcStats>* out);

}  // namespace scalar

// The walk over the arcs that every backend shares: make_arc(curve, begin, end) is called for each
// arc of at least min_points points, in curve order, and its ArcStats appended to out.
template <class MakeArc>
void ArcStatsWith(const Curves& curves, const Splits& splits, int min_points, std::vector<ArcStats>* out,
                  MakeArc&& make_arc) {
  for (int c = 0; c < curves.size(); ++c) {
    std::int32_t begin = curves.offset[c];
    const std::int32_t last = curves.offset[c + 1] - 1;
    for (std::int32_t s = splits.offset[c]; s <= splits.offset[c + 1]; ++s) {
      const std::int32_t end = (s < splits.offset[c + 1]) ? splits.index[s] : last;
      if (end - begin + 1 >= min_points) out->push_back(make_arc(c, begin, end));
      begin = end;
    }
  }
}

// The statistics read off single points: curve, range, sign class, end and middle points; the
// bounding box starts as the first point. The reductions over the points are left to the caller.
inline ArcStats ArcPointStats(const Curves& c, int curve, std::int32_t begin, std::int32_t end) {
  ArcStats a;
  a.curve = curve;
  a.begin = begin;
  a.end = end;
  a.sign_class = c.sign_class[curve];
  a.x0 = c.x[begin]; a.y0 = c.y[begin];
  a.x1 = c.x[end];   a.y1 = c.y[end];
  const std::int32_t mid = begin + (end - begin) / 2;
  a.xm = c.x[mid]; a.ym = c.y[mid];
  a.min_x = a.max_x = a.x0;
  a.min_y = a.max_y = a.y0;
  return a;
}

// The quadrant from the bulge b = (bx, by) and the gradient class (see the top of this file).
inline std::int8_t QuadrantFromBulge(std::uint8_t sign_class, std::int64_t bx, std::int64_t by) {
  if (sign_class == 2) {  // kEdgeMinus
    const std::int64_t s = bx - by;
    return s > 0 ? kQuadrantI : s < 0 ? kQuadrantIII : kQuadrantNone;
  }
  const std::int64_t s = bx + by;
  return s < 0 ? kQuadrantII : s > 0 ? kQuadrantIV : kQuadrantNone;
}

}  // namespace ellipsekit
