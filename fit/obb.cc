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

ObbSides MinAreaObb(const std::int32_t* x, const std::int32_t* y, int begin, int end,
                    std::vector<std::int64_t>* hull) {
  const int n = end - begin;
  ObbSides best;
  if (n <= 0) return best;
  // Points first (sorted, unique) in the back half, hull built in the front.
  hull->resize(static_cast<std::size_t>(3 * n));
  std::int64_t* pts = hull->data() + 2 * n;
  for (int i = 0; i < n; ++i) pts[i] = Pack(x[begin + i], y[begin + i]);
  std::sort(pts, pts + n);
  const int m = static_cast<int>(std::unique(pts, pts + n) - pts);
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
  double best_area = std::numeric_limits<double>::infinity();
  for (int i = 0; i < hn; ++i) {
    const std::int64_t a = h[i], b = h[(i + 1) % hn];
    const double ex = double(PX(b) - PX(a)), ey = double(PY(b) - PY(a));
    const double len = std::hypot(ex, ey);
    const double ux = ex / len, uy = ey / len;
    double lo = 0, hi = 0, height = 0;
    for (int j = 0; j < hn; ++j) {
      const double px = double(PX(h[j]) - PX(a)), py = double(PY(h[j]) - PY(a));
      const double along = px * ux + py * uy;
      lo = std::min(lo, along);
      hi = std::max(hi, along);
      height = std::max(height, std::abs(px * uy - py * ux));
    }
    const double width = hi - lo;
    if (width * height < best_area) {
      best_area = width * height;
      best.short_side = std::min(width, height);
      best.long_side = std::max(width, height);
    }
  }
  return best;
}

}  // namespace ellipsekit
