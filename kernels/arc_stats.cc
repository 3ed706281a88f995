#include "kernels/arc_stats.h"

#include <algorithm>

namespace ellipsekit::scalar {

namespace {

ArcStats MakeArc(const Curves& c, int curve, std::int32_t begin, std::int32_t end) {
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
  if (a.sign_class == 2) {  // kEdgeMinus
    const std::int64_t s = bx - by;
    a.quadrant = s > 0 ? kQuadrantI : s < 0 ? kQuadrantIII : kQuadrantNone;
  } else {
    const std::int64_t s = bx + by;
    a.quadrant = s < 0 ? kQuadrantII : s > 0 ? kQuadrantIV : kQuadrantNone;
  }
  return a;
}

}  // namespace

void ArcStatsFromSplits(const Curves& curves, const Splits& splits, int min_points,
                        std::vector<ArcStats>* out) {
  for (int c = 0; c < curves.size(); ++c) {
    std::int32_t begin = curves.offset[c];
    const std::int32_t last = curves.offset[c + 1] - 1;
    for (std::int32_t s = splits.offset[c]; s <= splits.offset[c + 1]; ++s) {
      const std::int32_t end = (s < splits.offset[c + 1]) ? splits.index[s] : last;
      if (end - begin + 1 >= min_points) out->push_back(MakeArc(curves, c, begin, end));
      begin = end;
    }
  }
}

}  // namespace ellipsekit::scalar
