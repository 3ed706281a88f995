#include "kernels/polyline.h"

#include <cmath>

namespace ellipsekit {

std::int32_t PolylineToleranceQ16(double tolerance_px) {
  return static_cast<std::int32_t>(std::lround(16.0 * tolerance_px * tolerance_px));
}

namespace scalar {

void Polyline(const Curves& curves, std::int32_t tol_q16, Polylines* out, std::vector<std::int32_t>* stack) {
  const std::int32_t* px = curves.x.data();
  const std::int32_t* py = curves.y.data();
  PolylineWith(curves, tol_q16, out, stack, [px, py](std::int32_t i, std::int32_t j, std::int64_t* best) {
    return FarthestPointInRange(px, py, i, j, i + 1, j, best);
  });
}

}  // namespace scalar
}  // namespace ellipsekit
