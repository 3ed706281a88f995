#include "fit/edge_coverage.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <numbers>

namespace ellipsekit {

namespace {

constexpr int kSectors = 64;
constexpr int kSamplesPerSector = 4;
constexpr int kSamples = kSectors * kSamplesPerSector;
constexpr int kFineSamples = 64;       // FineEdgeCoverage: one sample in the middle of each sector
constexpr double kFineDistance = 1.0;  // px, FineEdgeCoverage's band either side of the outline
constexpr int kClaimRadius = 2;        // px, ClaimEdges' neighbourhood (5x5)

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
  // with d without a root or a division.
  bool Within(double x, double y, double d) const {
    const double dx = x - e.cx, dy = y - e.cy;
    const double u = (dx * c + dy * s) * ia, v = (dy * c - dx * s) * ib;
    const double f = u * u + v * v - 1, gu = 2 * u * ia, gv = 2 * v * ib;
    return f * f <= d * d * (gu * gu + gv * gv);
  }
};

// The stride through the 256 samples that keeps consecutive ones about `spacing` px apart along
// the outline (Ramanujan's perimeter): a small ellipse needs far fewer than 256.
int SampleStep(const Ellipse& e, double spacing) {
  const double h = (e.a - e.b) * (e.a - e.b) / ((e.a + e.b) * (e.a + e.b));
  const double perimeter = std::numbers::pi * (e.a + e.b) * (1 + 3 * h / (10 + std::sqrt(4 - 3 * h)));
  if (!(perimeter < kSamples * spacing)) return 1;
  return std::max(1, static_cast<int>(kSamples * spacing / std::max(perimeter, 1.0)));
}

// Nearest integer, halves up (in reach of the frame, so no overflow); inline, unlike std::lround.
int RoundToInt(double v) { return static_cast<int>(std::floor(v + 0.5)); }

bool InReach(const Outline::Sample& p, const EdgeMapView& in) {
  return p.px > -3 && p.px < in.width + 2 && p.py > -3 && p.py < in.height + 2;
}

// Calls visit(x, y) for each edge pixel of the (2 r + 1)^2 window around (x0, y0), clipped to the
// frame, row by row, until it returns true; returns whether one did.
template <typename Visit>
bool VisitEdgesAround(const EdgeMapView& in, int x0, int y0, int r, Visit visit) {
  const int xa = std::max(x0 - r, 0), xb = std::min(x0 + r, in.width - 1);
  const int ya = std::max(y0 - r, 0), yb = std::min(y0 + r, in.height - 1);
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
      hit = VisitEdgesAround(in, x0, y0, 1, [&](int x, int y) {
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
  // Samples about kClaimRadius px apart are enough for the 5x5 neighbourhoods to overlap.
  const int step = SampleStep(e, kClaimRadius);
  for (int i = 0; i < kSamples; i += step) {
    const Outline::Sample p = outline.At(i);
    if (!InReach(p, in)) continue;
    const int x0 = RoundToInt(p.px), y0 = RoundToInt(p.py);
    VisitEdgesAround(in, x0, y0, kClaimRadius, [&](int x, int y) {
      const std::int32_t index = y * in.width + x;
      if (claims->mask[index] == 0 && GradientAlong(in, x, y, p.nx, p.ny)) {
        claims->mask[index] = 1;
        claims->claimed.push_back(index);
      }
      return false;
    });
  }
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
    hits += VisitEdgesAround(in, x0, y0, 1, [&](int x, int y) {
      return GradientAlong(in, x, y, p.nx, p.ny) && outline.Within(x, y, kFineDistance);
    });
  }
  return static_cast<double>(hits) / kFineSamples;
}

int EdgePointsNear(const EdgeMapView& in, const Ellipse& e, double distance, EdgeClaims* seen,
                   std::vector<std::int32_t>* xs, std::vector<std::int32_t>* ys) {
  const Outline outline(e);
  xs->clear();
  ys->clear();
  // Samples about 1 px apart are enough for the 3x3 neighbourhoods to overlap.
  const int step = SampleStep(e, 1);
  for (int i = 0; i < kSamples; i += step) {
    const Outline::Sample p = outline.At(i);
    if (!InReach(p, in)) continue;
    const int x0 = RoundToInt(p.px), y0 = RoundToInt(p.py);
    VisitEdgesAround(in, x0, y0, 1, [&](int x, int y) {
      const std::int32_t index = y * in.width + x;
      if (seen->mask[index] == 0 && GradientAlong(in, x, y, p.nx, p.ny) && outline.Within(x, y, distance)) {
        seen->mask[index] = 1;
        seen->claimed.push_back(index);
        xs->push_back(x);
        ys->push_back(y);
      }
      return false;
    });
  }
  seen->Clear();
  return static_cast<int>(xs->size());
}

}  // namespace ellipsekit
