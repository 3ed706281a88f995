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

#include <vector>

#include "kernels/arc_split.h"
#include "kernels/arc_types.h"

namespace ellipsekit::scalar {

// Appends one ArcStats per arc of every curve, in curve order. Arcs with fewer than
// min_points points are skipped (T_n, sec. II-B-1: "filtering ... used again").
void ArcStatsFromSplits(const Curves& curves, const Splits& splits, int min_points,
                        std::vector<ArcStats>* out);

}  // namespace ellipsekit::scalar
