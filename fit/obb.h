// OBB_min: the minimum-area oriented bounding box of a point set (sec. II-A, ref. [33]).
// Convex hull (Andrew's monotone chain, exact on integer points), then every hull edge is tried
// as a side of the box (the optimal box has a side on a hull edge), by rotating calipers: O(n).
#pragma once

#include <cstdint>
#include <vector>

namespace ellipsekit {

struct ObbSides {
  double short_side = 0;  // px
  double long_side = 0;   // px
};

// Points are (x[i], y[i]) for i in [begin, end). hull: scratch, resized to
// ObbScratchSize(end - begin, columns the points span) <= ObbScratchSize(n, n) entries.
std::int64_t ObbScratchSize(std::int64_t points, std::int64_t columns);

// A sufficient test for MinAreaObb(...).short_side >= t, in O(1): the box's short side is at least
// the point set's width across it, which is at least the smallest altitude of any triangle of
// its points (2 area / longest side). Tries two triangles of the chain (ends and middle; thirds);
// false means "not proven", not "thinner than t".
bool ObbShortSideAtLeast(const std::int32_t* x, const std::int32_t* y, int begin, int end, double t);

// Bounds on MinAreaObb(...).short_side s from one pass over the points, without a hull:
//   upper: the box aligned with the chord (first to last point; the x axis when they coincide)
//     has area A >= s l of the minimal box, whose diagonal is at least the points' diameter D,
//     itself at least that box's longer side: s^2 + l^2 >= D^2 with l >= s. s l grows with s
//     under these constraints, so s <= g^-1(A), g(s) = s sqrt(D^2 - s^2) up to s = D / sqrt 2 and
//     s^2 beyond.
//   lower: the minimal box's short side is at least the points' width across it, which is at
//     least the minimum width of the hull of any of the points: here the ends and the extreme
//     points along and across the chord (<= 6 points; their hull edges by brute force).
// Each bound carries a relative margin of 1e-9 toward the safe side, so `lower >= t` proves
// s >= t and `upper < t` proves s < t despite rounding. The lower bound costs a second pass and
// is computed only when upper >= t (else it is 0: s < t is already known); t = 0 gives both.
struct ObbShortSideBounds {
  double lower = 0;
  double upper = 0;
};
ObbShortSideBounds ShortSideBounds(const std::int32_t* x, const std::int32_t* y, int begin, int end, double t);

ObbSides MinAreaObb(const std::int32_t* x, const std::int32_t* y, int begin, int end,
                    std::vector<std::int64_t>* hull);

}  // namespace ellipsekit
