#include "fit/edge_coverage.h"

#include <array>
#include <cmath>
#include <cstddef>
#include <numbers>

namespace ellipsekit {

namespace {
constexpr int kSectors = 64;
constexpr int kSamplesPerSector = 4;
}  // namespace

double EdgeCoverage(const EdgeMapView& in, const Ellipse& e, double min_share) {
  // (cos t, sin t) of the 256 sample angles, computed once.
  static const auto kUnit = [] {
    std::array<std::array<double, 2>, kSectors * kSamplesPerSector> unit{};
    for (std::size_t i = 0; i < unit.size(); ++i) {
      const double t = (i + 0.5) * (2 * std::numbers::pi / unit.size());
      unit[i] = {std::cos(t), std::sin(t)};
    }
    return unit;
  }();
  const double c = std::cos(e.theta), s = std::sin(e.theta);
  const int needed = static_cast<int>(std::ceil(min_share * kSectors));
  int covered = 0;
  for (int sector = 0; sector < kSectors; ++sector) {
    if (covered + (kSectors - sector) < needed) break;  // min_share is out of reach
    bool hit = false;
    for (int k = 0; k < kSamplesPerSector && !hit; ++k) {
      const auto [ct, st] = kUnit[sector * kSamplesPerSector + k];
      const double px = e.cx + e.a * ct * c - e.b * st * s, py = e.cy + e.a * ct * s + e.b * st * c;
      if (!(px > -2 && px < in.width + 1 && py > -2 && py < in.height + 1)) continue;  // no pixel in reach
      // The outward normal at t: (b cos t, a sin t) in the ellipse frame.
      const double nu = e.b * ct, nv = e.a * st;
      const double nx = nu * c - nv * s, ny = nu * s + nv * c;
      const int x0 = static_cast<int>(std::lround(px)), y0 = static_cast<int>(std::lround(py));
      for (int y = y0 - 1; y <= y0 + 1 && !hit; ++y) {
        if (y < 0 || y >= in.height) continue;
        for (int x = x0 - 1; x <= x0 + 1 && !hit; ++x) {
          if (x < 0 || x >= in.width || in.edge_map[y * in.stride + x] == 0) continue;
          hit = GradientAlongNormal(in.dx[y * in.grad_stride + x], in.dy[y * in.grad_stride + x], nx, ny);
        }
      }
    }
    covered += hit;
  }
  return static_cast<double>(covered) / kSectors;
}

}  // namespace ellipsekit
