#include "fit/edge_coverage.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <numbers>

#include "fit/ellipse_rows.h"

namespace ellipsekit {

namespace {

constexpr int kSectors = 64;
constexpr int kSamplesPerSector = 4;
constexpr int kSamples = kSectors * kSamplesPerSector;
constexpr int kFineSamples = 64;       // FineEdgeCoverage: one sample in the middle of each sector
constexpr double kFineDistance = 1.0;  // px, FineEdgeCoverage's band either side of the outline
// px, ClaimEdges' band either side of the outline: as far as the 5x5 windows around samples 2 px
// apart that it replaced reached (measured: 2.5 px let in 3 more false detections on crowded seed 1
// and 2 on hard seed 2).
constexpr double kClaimDistance = 3.0;
// StripedShare: an outline sample is backed when the gradient along its normal within 1 px
// reaches kStripeMinGradient (L1 Sobel units: a step of 2 grey levels after the blur); it lies in
// a stripe pattern when, on both sides, 2-5 px away, the gradient along the normal turns to the
// opposite sign at kStripeRelative or more of the outline's own.
constexpr int kStripeMinGradient = 8;
constexpr int kStripeNear = 2, kStripeFar = 5;  // px along the normal
constexpr double kStripeRelative = 0.4;

// (cos t, sin t) of the 256 sample angles, computed once.
const std::array<std::array<double, 2>, kSamples>& UnitSamples() {
  static const auto kUnit = [] {
    std::array<std::array<double, 2>, kSamples> unit{};
    for (std::size_t i = 0; i < unit.size(); ++i) {
      const double t = (i + 0.5) * (2 * std::numbers::pi / unit.size());
      unit[i] = {std::cos(t), std::sin(t)};
    }
    return unit;
  }();
  return kUnit;
}

// The ellipse in its own frame, and its sample points with their normals.
struct Outline {
  const Ellipse& e;
  double c, s, ia, ib;
  explicit Outline(const Ellipse& el)
      : e(el), c(std::cos(el.theta)), s(std::sin(el.theta)), ia(1 / el.a), ib(1 / el.b) {}

  struct Sample {
    double px, py, nx, ny;
  };
  Sample At(int i) const {
    const auto [ct, st] = UnitSamples()[i];
    // The outward normal at t: (b cos t, a sin t) in the ellipse frame.
    const double nu = e.b * ct, nv = e.a * st;
    return {e.cx + e.a * ct * c - e.b * st * s, e.cy + e.a * ct * s + e.b * st * c, nu * c - nv * s,
            nu * s + nv * c};
  }
  // First-order distance of (x, y) to the ellipse, |F| / |grad F|, F = u^2 + v^2 - 1, compared
  // with d without a root or a division; (*nx, *ny) = grad F there, the outward normal.
  bool Within(double x, double y, double d, double* nx = nullptr, double* ny = nullptr) const {
    const double dx = x - e.cx, dy = y - e.cy;
    const double u = (dx * c + dy * s) * ia, v = (dy * c - dx * s) * ib;
    const double f = u * u + v * v - 1, gu = 2 * u * ia, gv = 2 * v * ib;
    if (nx != nullptr) {
      *nx = gu * c - gv * s;
      *ny = gu * s + gv * c;
    }
    return f * f <= d * d * (gu * gu + gv * gv);
  }
};

// Nearest integer, halves up (in reach of the frame, so no overflow); inline, unlike std::lround.
int RoundToInt(double v) { return static_cast<int>(std::floor(v + 0.5)); }

bool InReach(const Outline::Sample& p, const EdgeMapView& in) {
  return p.px > -3 && p.px < in.width + 2 && p.py > -3 && p.py < in.height + 2;
}

// Calls visit(x, y) for each edge pixel of the 3x3 window around (x0, y0), clipped to the frame,
// row by row, until it returns true; returns whether one did. Inside the frame the window's nine
// bytes are read without a branch into a 9-bit mask (most windows hold no edge pixel).
template <typename Visit>
bool VisitEdgesAround(const EdgeMapView& in, int x0, int y0, Visit visit) {
  if (x0 >= 1 && x0 <= in.width - 2 && y0 >= 1 && y0 <= in.height - 2) {
    const std::uint8_t* row = in.edge_map + (y0 - 1) * in.stride + (x0 - 1);
    unsigned mask = 0;
    for (int k = 0; k < 9; ++k) mask |= static_cast<unsigned>(row[(k / 3) * in.stride + k % 3] != 0) << k;
    for (; mask != 0; mask &= mask - 1) {
      const int k = std::countr_zero(mask);
      if (visit(x0 - 1 + k % 3, y0 - 1 + k / 3)) return true;
    }
    return false;
  }
  const int xa = std::max(x0 - 1, 0), xb = std::min(x0 + 1, in.width - 1);
  const int ya = std::max(y0 - 1, 0), yb = std::min(y0 + 1, in.height - 1);
  for (int y = ya; y <= yb; ++y) {
    const std::uint8_t* row = in.edge_map + y * in.stride;
    for (int x = xa; x <= xb; ++x) {
      if (row[x] != 0 && visit(x, y)) return true;
    }
  }
  return false;
}

// Whether the gradient at (x, y), inside the frame, lies along (nx, ny).
bool GradientAlong(const EdgeMapView& in, int x, int y, double nx, double ny) {
  return GradientAlongNormal(in.dx[y * in.grad_stride + x], in.dy[y * in.grad_stride + x], nx, ny);
}

// Calls visit(x, y) for each edge pixel of the frame between the ellipses with semi-axes
// (a - margin, b - margin) and (a + margin, b + margin), row by row, each pixel once. Work: the
// pixels of that annulus, empty runs skipped 8 bytes at a time.
template <typename Visit>
void ForEachEdgeInBand(const EdgeMapView& in, const Ellipse& e, double margin, Visit visit) {
  const EllipseRows outer(e.theta, e.a + margin, e.b + margin);
  const bool has_inner = e.b > margin;
  const EllipseRows inner(e.theta, has_inner ? e.a - margin : 1, has_inner ? e.b - margin : 1);
  const double h = outer.half_height();
  if (!(e.cy + h >= 0 && e.cy - h <= in.height - 1)) return;
  const int ya = static_cast<int>(std::ceil(std::max(e.cy - h, 0.0)));
  const int yb = static_cast<int>(std::floor(std::min(e.cy + h, in.height - 1.0)));
  auto scan = [&](const std::uint8_t* row, int y, double from, double to) {  // x in [from, to]
    // Clipped in doubles before any conversion: a huge or degenerate ellipse gives infinite or
    // NaN chord ends, and NaN fails the test.
    const double lo = std::max(from, 0.0), hi = std::min(to, in.width - 1.0);
    if (!(lo <= hi)) return;
    const int xa = static_cast<int>(std::ceil(lo));
    const int end = static_cast<int>(std::floor(hi)) + 1;
    for (int x = FirstNonZeroByte(row, xa, end); x < end; x = FirstNonZeroByte(row, x + 1, end)) visit(x, y);
  };
  for (int y = ya; y <= yb; ++y) {
    const double dy = y - e.cy;
    double xo0, xo1;
    if (!outer.Span(dy, &xo0, &xo1)) continue;
    const std::uint8_t* row = in.edge_map + y * in.stride;
    double xi0, xi1;
    // The inner chord's pixels a pixel or more inside its ends are inside the inner ellipse.
    if (has_inner && inner.Span(dy, &xi0, &xi1) && xi1 - xi0 > 2) {
      scan(row, y, e.cx + xo0, e.cx + xi0 + 1);
      scan(row, y, e.cx + xi1 - 1, e.cx + xo1);
    } else {
      scan(row, y, e.cx + xo0, e.cx + xo1);
    }
  }
}

}  // namespace

void EdgeClaims::Resize(int width, int height) {
  mask.assign(static_cast<std::size_t>(width) * height, 0);
  claimed.clear();
  claimed.reserve(mask.size() / 16);  // grows (and keeps) when more is claimed
}

void EdgeClaims::Clear() {
  for (const std::int32_t i : claimed) mask[i] = 0;
  claimed.clear();
}

double EdgeCoverage(const EdgeMapView& in, const Ellipse& e, double min_share, const EdgeClaims* exclude) {
  const Outline outline(e);
  const int needed = static_cast<int>(std::ceil(min_share * kSectors));
  int covered = 0;
  for (int sector = 0; sector < kSectors; ++sector) {
    if (covered + (kSectors - sector) < needed) break;  // min_share is out of reach
    bool hit = false;
    for (int k = 0; k < kSamplesPerSector && !hit; ++k) {
      const Outline::Sample p = outline.At(sector * kSamplesPerSector + k);
      if (!InReach(p, in)) continue;
      const int x0 = RoundToInt(p.px), y0 = RoundToInt(p.py);
      hit = VisitEdgesAround(in, x0, y0, [&](int x, int y) {
        return GradientAlong(in, x, y, p.nx, p.ny) && (exclude == nullptr || exclude->mask[y * in.width + x] == 0);
      });
    }
    covered += hit;
  }
  return static_cast<double>(covered) / kSectors;
}

double InFrameShare(const EdgeMapView& in, const Ellipse& e) {
  const Outline outline(e);
  int inside = 0;
  for (int sector = 0; sector < kSectors; ++sector) {
    const Outline::Sample p = outline.At(sector * kSamplesPerSector + kSamplesPerSector / 2);
    inside += p.px >= 0 && p.px <= in.width - 1 && p.py >= 0 && p.py <= in.height - 1;
  }
  return static_cast<double>(inside) / kSectors;
}

void ClaimEdges(const EdgeMapView& in, const Ellipse& e, EdgeClaims* claims) {
  const Outline outline(e);
  ForEachEdgeInBand(in, e, kClaimDistance + 1, [&](int x, int y) {
    const std::int32_t index = y * in.width + x;
    double nx, ny;
    if (claims->mask[index] == 0 && outline.Within(x, y, kClaimDistance, &nx, &ny) && GradientAlong(in, x, y, nx, ny)) {
      claims->mask[index] = 1;
      claims->claimed.push_back(index);
    }
  });
}

double FineEdgeCoverage(const EdgeMapView& in, const Ellipse& e, double to_beat) {
  const Outline outline(e);
  const int needed = static_cast<int>(std::floor(to_beat * kFineSamples)) + 1;  // hits that beat to_beat
  int hits = 0;
  for (int i = 0; i < kFineSamples; ++i) {
    if (hits + (kFineSamples - i) < needed) break;  // to_beat is out of reach
    const Outline::Sample p = outline.At(i * (kSamples / kFineSamples) + kSamples / kFineSamples / 2);
    if (!InReach(p, in)) continue;
    const int x0 = RoundToInt(p.px), y0 = RoundToInt(p.py);
    hits += VisitEdgesAround(in, x0, y0, [&](int x, int y) {
      return GradientAlong(in, x, y, p.nx, p.ny) && outline.Within(x, y, kFineDistance);
    });
  }
  return static_cast<double>(hits) / kFineSamples;
}

int EdgePointsNear(const EdgeMapView& in, const Ellipse& e, double distance, std::vector<std::int32_t>* xs,
                   std::vector<std::int32_t>* ys) {
  const Outline outline(e);
  xs->clear();
  ys->clear();
  ForEachEdgeInBand(in, e, distance + 1, [&](int x, int y) {
    double nx, ny;
    if (xs->size() < xs->capacity() && outline.Within(x, y, distance, &nx, &ny) && GradientAlong(in, x, y, nx, ny)) {
      xs->push_back(x);
      ys->push_back(y);
    }
  });
  return static_cast<int>(xs->size());
}

double StripedShare(const EdgeMapView& in, const Ellipse& e, double to_exceed) {
  const Outline outline(e);
  int backed = 0, striped = 0;
  for (int i = 0; i < kFineSamples; ++i) {
    // Even if every sample left were backed and striped, the share could not exceed to_exceed.
    if ((striped + kFineSamples - i) * (1 - to_exceed) <= to_exceed * (backed - striped)) break;
    const Outline::Sample p = outline.At(i * (kSamples / kFineSamples) + kSamples / kFineSamples / 2);
    const double norm = std::hypot(p.nx, p.ny);
    if (!(norm > 0)) continue;
    const double ux = p.nx / norm, uy = p.ny / norm;
    // The gradient along the unit normal at t px out (in when t < 0); outside the frame: none.
    // Tested in doubles before rounding: an ellipse far outside the frame (or NaN) stays out.
    auto along = [&](int t, bool* inside) {
      const double fx = p.px + t * ux, fy = p.py + t * uy;
      *inside = fx >= -0.5 && fy >= -0.5 && fx < in.width - 0.5 && fy < in.height - 0.5;
      if (!*inside) return 0.0;
      const int x = RoundToInt(fx), y = RoundToInt(fy);
      const std::ptrdiff_t k = static_cast<std::ptrdiff_t>(y) * in.grad_stride + x;
      return in.dx[k] * ux + in.dy[k] * uy;
    };
    double g0 = 0;
    bool all_inside = true;
    for (int t = -1; t <= 1; ++t) {
      bool inside;
      const double g = along(t, &inside);
      all_inside = all_inside && inside;
      if (std::abs(g) > std::abs(g0)) g0 = g;
    }
    if (!all_inside || std::abs(g0) < kStripeMinGradient) continue;
    ++backed;
    // Signed so that the outline's own edge is positive: a stripe's edges are negative.
    const double sign = g0 > 0 ? 1 : -1, opposite = -kStripeRelative * std::abs(g0);
    auto opposite_edge = [&](int side) {  // +1 out, -1 in
      for (int t = kStripeNear; t <= kStripeFar; ++t) {
        bool inside;
        if (sign * along(side * t, &inside) <= opposite) return true;
      }
      return false;
    };
    striped += opposite_edge(1) && opposite_edge(-1);
  }
  return backed == 0 ? 0 : static_cast<double>(striped) / backed;
}

}  // namespace ellipsekit
