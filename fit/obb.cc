#include "fit/obb.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ellipsekit {

namespace {

// A point packed as (x << 32) | y with a bias, so sorting the packed values sorts by (x, y).
constexpr std::int64_t kBias = 1 << 20;
std::int64_t Pack(std::int32_t x, std::int32_t y) { return ((x + kBias) << 32) | (y + kBias); }
std::int64_t PX(std::int64_t p) { return (p >> 32) - kBias; }
std::int64_t PY(std::int64_t p) { return (p & 0xffffffff) - kBias; }

std::int64_t Cross(std::int64_t o, std::int64_t a, std::int64_t b) {
  return (PX(a) - PX(o)) * (PY(b) - PY(o)) - (PY(a) - PY(o)) * (PX(b) - PX(o));
}

}  // namespace

std::int64_t ObbScratchSize(std::int64_t points, std::int64_t columns) {
  return 2 * points + 4 * columns;  // the hull stack (<= 2 per point), then the columns
}

bool ObbShortSideAtLeast(const std::int32_t* x, const std::int32_t* y, int begin, int end, double t) {
  const int n = end - begin;
  if (n < 3) return false;
  // Smallest altitude of triangle (i, j, k) >= t  <=>  (2 area)^2 >= t^2 longest side^2; integer
  // coordinates keep both sides exact in doubles.
  auto proven_by = [&](int i, int j, int k) {
    const std::int64_t ax = x[j] - x[i], ay = y[j] - y[i], bx = x[k] - x[i], by = y[k] - y[i];
    const std::int64_t cx = x[k] - x[j], cy = y[k] - y[j];
    const double twice_area = double(ax * by - ay * bx);
    const double longest2 = double(std::max({ax * ax + ay * ay, bx * bx + by * by, cx * cx + cy * cy}));
    return twice_area * twice_area >= t * t * longest2;
  };
  // An open arc: its ends and middle; a closed curve (ends adjacent): thirds.
  return proven_by(begin, begin + n / 2, end - 1) || proven_by(begin, begin + n / 3, begin + 2 * n / 3);
}

ObbShortSideBounds ShortSideBounds(const std::int32_t* x, const std::int32_t* y, int begin, int end, double t) {
  ObbShortSideBounds bounds;
  if (end - begin < 2) return bounds;
  double ux = x[end - 1] - x[begin], uy = y[end - 1] - y[begin];
  if (ux == 0 && uy == 0) ux = 1;
  // Projections along and across (ux, uy), in units of |u| px: integers, exact in doubles.
  auto along = [&](int i) { return (x[i] - x[begin]) * ux + (y[i] - y[begin]) * uy; };
  auto across = [&](int i) { return (x[i] - x[begin]) * uy - (y[i] - y[begin]) * ux; };
  double lo_along = 0, hi_along = 0, lo_across = 0, hi_across = 0;
  for (int i = begin + 1; i < end; ++i) {
    lo_along = std::min(lo_along, along(i));
    hi_along = std::max(hi_along, along(i));
    lo_across = std::min(lo_across, across(i));
    hi_across = std::max(hi_across, across(i));
  }
  const double u2 = ux * ux + uy * uy;
  const double length = hi_along - lo_along, width = hi_across - lo_across;
  const double area = length * width / u2;                          // px^2
  const double d2 = std::max(length * length, width * width) / u2;  // D^2 >= the longer side^2
  // g^-1(A): s^2 = 2 A^2 / (D^2 + sqrt(D^4 - 4 A^2)) while 2 A <= D^2 (no cancellation), else A.
  const double upper2 =
      2 * area <= d2 ? 2 * area * area / (d2 + std::sqrt(std::max(0.0, d2 * d2 - 4 * area * area))) : area;
  bounds.upper = std::sqrt(upper2) * (1 + 1e-9);
  if (bounds.upper < t) return bounds;  // decided: the hull below is not needed

  // The hull of the extreme points: a pair (i, j) is a hull edge when every point lies on one
  // side of its line; the minimum width is the least, over hull edges, of the farthest point's
  // distance from the edge's line (0 when all are collinear).
  int idx[6] = {begin, end - 1, begin, begin, begin, begin};
  for (int i = begin + 1; i < end; ++i) {
    if (along(i) == lo_along) idx[2] = i;
    if (along(i) == hi_along) idx[3] = i;
    if (across(i) == lo_across) idx[4] = i;
    if (across(i) == hi_across) idx[5] = i;
  }
  double min_width2 = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 6; ++a) {
    for (int b = a + 1; b < 6; ++b) {
      const std::int64_t ex = x[idx[b]] - x[idx[a]], ey = y[idx[b]] - y[idx[a]];
      if (ex == 0 && ey == 0) continue;
      std::int64_t lo = 0, hi = 0;
      for (int k = 0; k < 6; ++k) {
        const std::int64_t cross = ex * (y[idx[k]] - y[idx[a]]) - ey * (x[idx[k]] - x[idx[a]]);
        lo = std::min(lo, cross);
        hi = std::max(hi, cross);
      }
      if (lo < 0 && hi > 0) continue;  // not a hull edge
      const double far = double(std::max(hi, -lo));
      min_width2 = std::min(min_width2, far * far / double(ex * ex + ey * ey));
    }
  }
  if (min_width2 != std::numeric_limits<double>::infinity()) bounds.lower = std::sqrt(min_width2) * (1 - 1e-9);
  return bounds;
}

ObbSides MinAreaObb(const std::int32_t* x, const std::int32_t* y, int begin, int end,
                    std::vector<std::int64_t>* hull) {
  const int n = end - begin;
  ObbSides best;
  if (n <= 0) return best;
  // The hull of the points is the hull of each column's lowest and highest point, and listing
  // those column by column gives them sorted by (x, y) and unique without a sort: O(n + columns).
  int min_x = x[begin], max_x = x[begin];
  for (int i = begin + 1; i < end; ++i) {
    min_x = std::min(min_x, x[i]);
    max_x = std::max(max_x, x[i]);
  }
  const int columns = max_x - min_x + 1;  // <= n: the points are an 8-connected chain or fewer
  hull->resize(static_cast<std::size_t>(ObbScratchSize(n, columns)));
  std::int64_t* column_lo = hull->data() + 2 * n;   // lowest y per column (kEmpty: none)
  std::int64_t* column_hi = column_lo + columns;    // highest y per column
  std::int64_t* pts = column_hi + columns;          // up to 2 per column
  constexpr std::int64_t kEmpty = std::numeric_limits<std::int64_t>::max();
  std::fill(column_lo, column_lo + columns, kEmpty);
  std::fill(column_hi, column_hi + columns, std::numeric_limits<std::int64_t>::min());
  for (int i = begin; i < end; ++i) {
    const int c = x[i] - min_x;
    column_lo[c] = std::min<std::int64_t>(column_lo[c], y[i]);
    column_hi[c] = std::max<std::int64_t>(column_hi[c], y[i]);
  }
  int m = 0;
  for (int c = 0; c < columns; ++c) {
    if (column_lo[c] == kEmpty) continue;
    const std::int32_t cx = min_x + c;
    pts[m++] = Pack(cx, static_cast<std::int32_t>(column_lo[c]));
    if (column_hi[c] != column_lo[c]) pts[m++] = Pack(cx, static_cast<std::int32_t>(column_hi[c]));
  }
  std::int64_t* h = hull->data();
  int k = 0;
  for (int i = 0; i < m; ++i) {  // lower hull
    while (k >= 2 && Cross(h[k - 2], h[k - 1], pts[i]) <= 0) --k;
    h[k++] = pts[i];
  }
  for (int i = m - 2, lower = k + 1; i >= 0; --i) {  // upper hull
    while (k >= lower && Cross(h[k - 2], h[k - 1], pts[i]) <= 0) --k;
    h[k++] = pts[i];
  }
  const int hn = std::max(1, k - 1);
  if (hn <= 2) {  // a point or a segment
    const double len = hn == 2 ? std::hypot(double(PX(h[1]) - PX(h[0])), double(PY(h[1]) - PY(h[0]))) : 0.0;
    return {0.0, len};
  }
  // Rotating calipers: as the box side turns counter-clockwise from hull edge to hull edge, the
  // vertices farthest along it (ahead, behind) and across it only move forward, so each edge costs
  // O(1) amortised. Integer vertices keep neighbouring projections at least 1 / |edge| apart unless
  // they are exactly equal, so the walks stop at the true extremes (ties give equal values).
  double best_area = std::numeric_limits<double>::infinity();
  int ahead = 0, behind = 0, across = 0;  // extreme vertices for the current edge
  for (int i = 0; i < hn; ++i) {
    const std::int64_t a = h[i], b = h[(i + 1) % hn];
    const double ex = double(PX(b) - PX(a)), ey = double(PY(b) - PY(a));
    const double len = std::sqrt(ex * ex + ey * ey);  // exact squares: rounds as hypot does
    const double ux = ex / len, uy = ey / len;
    auto along = [&](int j) { return double(PX(h[j]) - PX(a)) * ux + double(PY(h[j]) - PY(a)) * uy; };
    auto height_of = [&](int j) { return std::abs(double(PX(h[j]) - PX(a)) * uy - double(PY(h[j]) - PY(a)) * ux); };
    if (i == 0) {  // the first edge finds its extremes by a full scan
      for (int j = 1; j < hn; ++j) {
        if (along(j) > along(ahead)) ahead = j;
        if (along(j) < along(behind)) behind = j;
        if (height_of(j) > height_of(across)) across = j;
      }
    } else {
      for (int k = 0; k < hn && along((ahead + 1) % hn) >= along(ahead); ++k) ahead = (ahead + 1) % hn;
      for (int k = 0; k < hn && along((behind + 1) % hn) <= along(behind); ++k) behind = (behind + 1) % hn;
      for (int k = 0; k < hn && height_of((across + 1) % hn) >= height_of(across); ++k) across = (across + 1) % hn;
    }
    const double width = std::max(0.0, along(ahead)) - std::min(0.0, along(behind));
    const double height = height_of(across);
    if (width * height < best_area) {
      best_area = width * height;
      best.short_side = std::min(width, height);
      best.long_side = std::max(width, height);
    }
  }
  return best;
}

}  // namespace ellipsekit
