#include "kernels/polyline.h"

#include <cmath>
#include <cstdlib>

namespace ellipsekit {

std::int32_t PolylineToleranceQ16(double tolerance_px) {
  return static_cast<std::int32_t>(std::lround(16.0 * tolerance_px * tolerance_px));
}

namespace scalar {

void Polyline(const Curves& curves, std::int32_t tol_q16, Polylines* out, std::vector<std::int32_t>* stack) {
  out->clear();
  const std::int32_t* px = curves.x.data();
  const std::int32_t* py = curves.y.data();
  for (int c = 0; c < curves.size(); ++c) {
    const std::int32_t first = curves.offset[c], last = curves.offset[c + 1] - 1;
    out->vertex.push_back(first);
    if (last > first) {
      stack->clear();
      stack->push_back(first);
      stack->push_back(last);
      while (!stack->empty()) {
        const std::int32_t j = stack->back(); stack->pop_back();
        const std::int32_t i = stack->back(); stack->pop_back();
        const std::int64_t cx = px[j] - px[i], cy = py[j] - py[i];
        std::int64_t best = -1;
        std::int32_t best_k = -1;
        for (std::int32_t k = i + 1; k < j; ++k) {
          const std::int64_t cr = std::llabs(cx * (py[k] - py[i]) - cy * (px[k] - px[i]));
          if (cr > best) { best = cr; best_k = k; }
        }
        const std::int64_t len2 = cx * cx + cy * cy;
        std::int32_t split = -1;
        if (best_k >= 0 && 16 * best * best > static_cast<std::int64_t>(tol_q16) * len2) {
          split = best_k;
        } else if ((std::llabs(cx) > kMaxSegmentComponent || std::llabs(cy) > kMaxSegmentComponent) && j - i >= 2) {
          split = i + (j - i) / 2;
        }
        if (split >= 0) {
          // Right half below the left half, so vertices come out in increasing order.
          stack->push_back(split); stack->push_back(j);
          stack->push_back(i); stack->push_back(split);
        } else {
          out->vertex.push_back(j);
        }
      }
    }
    out->offset.push_back(static_cast<std::int32_t>(out->vertex.size()));
  }
}

}  // namespace scalar
}  // namespace ellipsekit
