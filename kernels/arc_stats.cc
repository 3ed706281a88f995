#include "kernels/arc_stats.h"

#include <algorithm>

namespace ellipsekit::scalar {

namespace {

ArcStats MakeArc(const Curves& c, int curve, std::int32_t begin, std::int32_t end) {
  ArcStats a = ArcPointStats(c, curve, begin, end);
  // Bulge: the offsets 2 p_i - (first + last) summed over every point (exact in int64).
  std::int64_t bx = 0, by = 0;
  for (std::int32_t i = begin; i <= end; ++i) {
    a.min_x = std::min(a.min_x, c.x[i]); a.max_x = std::max(a.max_x, c.x[i]);
    a.min_y = std::min(a.min_y, c.y[i]); a.max_y = std::max(a.max_y, c.y[i]);
    bx += 2 * c.x[i] - (a.x0 + a.x1);
    by += 2 * c.y[i] - (a.y0 + a.y1);
  }
  const std::int32_t k = std::clamp((end - begin + 1) / 4, 1, 4);
  for (std::int32_t i = 0; i < k; ++i) {
    a.g0x += c.gx[begin + i]; a.g0y += c.gy[begin + i];
    a.g1x += c.gx[end - i];   a.g1y += c.gy[end - i];
  }
  a.quadrant = QuadrantFromBulge(a.sign_class, bx, by);
  return a;
}

}  // namespace

void ArcStatsFromSplits(const Curves& curves, const Splits& splits, int min_points,
                        std::vector<ArcStats>* out) {
  ArcStatsWith(curves, splits, min_points, out,
               [&curves](int c, std::int32_t begin, std::int32_t end) { return MakeArc(curves, c, begin, end); });
}

}  // namespace ellipsekit::scalar
