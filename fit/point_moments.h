// Raw moments of a point set up to order 4, so that a least-squares conic fit over a group of arcs
// costs O(1) per group instead of O(points): each arc's moments are summed once per frame and a
// group's scatter matrices are assembled from its arcs' moments (conic_refine.h).
#pragma once

#include <cstdint>

namespace ellipsekit {

inline constexpr int kMomentOrder = 4;

// m[a][b] = sum over the points of (x - ox)^a (y - oy)^b, for a + b <= kMomentOrder (entries with
// a + b > kMomentOrder are zero). The origin is kept near the points so the sums stay accurate.
struct PointMoments {
  double ox = 0, oy = 0;
  double m[kMomentOrder + 1][kMomentOrder + 1] = {};
};

// Moments of the points (x[i], y[i]), i in [begin, end], about the integer origin (ox, oy).
// Exact for arcs up to ~4000 px across (every sum is an integer below 2^53).
PointMoments MomentsOfPoints(const std::int32_t* x, const std::int32_t* y, int begin, int end,
                             std::int32_t ox, std::int32_t oy);
// The same for points at fractions of a pixel (fit/image_refit.h); the sums are then rounded.
PointMoments MomentsOfPoints(const double* x, const double* y, int begin, int end, double ox, double oy);

// Adds p's moments, re-expressed about acc's origin, to *acc (binomial expansion of the shift).
void AddShiftedMoments(const PointMoments& p, PointMoments* acc);

}  // namespace ellipsekit
