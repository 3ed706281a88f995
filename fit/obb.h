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

// A sufficient test for MinAreaObb(...).short_side < t, in one pass over the points: the box
// aligned with the chord (first to last point) has area A >= s l of the minimal box, whose
// diagonal covers the chord c (s^2 + l^2 >= c^2, so l >= c / sqrt 2): s <= sqrt(2) A / c. False
// means "not proven".
bool ObbShortSideBelow(const std::int32_t* x, const std::int32_t* y, int begin, int end, double t);

ObbSides MinAreaObb(const std::int32_t* x, const std::int32_t* y, int begin, int end,
                    std::vector<std::int64_t>* hull);

}  // namespace ellipsekit
