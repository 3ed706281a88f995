#include "kernels/arc_split.h"

#include <cmath>
#include <cstdlib>
#include <numbers>

namespace ellipsekit {

std::int64_t SplitTanQ16(double split_angle_deg) {
  return std::llround(65536.0 * std::tan(split_angle_deg * std::numbers::pi / 180.0));
}

namespace scalar {

namespace {

struct Turn {
  std::int64_t re, im;  // z = conj(a) * b
};

Turn TurnAt(const Curves& c, std::int32_t p0, std::int32_t p1, std::int32_t p2) {
  const std::int64_t ax = c.x[p1] - c.x[p0], ay = c.y[p1] - c.y[p0];
  const std::int64_t bx = c.x[p2] - c.x[p1], by = c.y[p2] - c.y[p1];
  return {ax * bx + ay * by, ax * by - ay * bx};
}

int Sign(std::int64_t v) { return (v > 0) - (v < 0); }

}  // namespace

void ArcSplit(const Curves& curves, const Polylines& polylines, std::int64_t tan_q16, Splits* out) {
  out->clear();
  for (int c = 0; c < curves.size(); ++c) {
    const std::int32_t* v = polylines.vertex.data() + polylines.offset[c];
    const int nv = polylines.offset[c + 1] - polylines.offset[c];
    const std::size_t start = out->index.size();
    // Interior vertices are 1 .. nv - 2; compare each with the next one.
    for (int k = 1; k + 2 < nv; ++k) {
      const Turn z0 = TurnAt(curves, v[k - 1], v[k], v[k + 1]);
      const Turn z1 = TurnAt(curves, v[k], v[k + 1], v[k + 2]);
      std::int32_t split = -1;
      if (Sign(z0.im) * Sign(z1.im) < 0) {
        split = v[k] + (v[k + 1] - v[k]) / 2;
      } else {
        const std::int64_t wre = z1.re * z0.re + z1.im * z0.im;
        const std::int64_t wim = z1.im * z0.re - z1.re * z0.im;
        if (wre <= 0 || 65536 * std::llabs(wim) > tan_q16 * wre) {
          const bool second_turns_more = z0.re * std::llabs(z1.im) - std::llabs(z0.im) * z1.re > 0;
          split = second_turns_more ? v[k + 1] : v[k];
        }
      }
      if (split >= 0 && (out->index.size() == start || out->index.back() != split)) {
        out->index.push_back(split);
      }
    }
    out->offset.push_back(static_cast<std::int32_t>(out->index.size()));
  }
}

}  // namespace scalar
}  // namespace ellipsekit
