#include "fit/edge_refit.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>

#include "fit/arc.h"
#include "fit/clustering.h"
#include "fit/conic_refine.h"
#include "fit/point_moments.h"

namespace ellipsekit {

namespace {
constexpr int kMinPoints = 12;
}  // namespace

void EdgeRefitScratch::Reserve(int width, int height) {
  const std::size_t room = 8 * (static_cast<std::size_t>(width) + height);
  x.reserve(room);
  y.reserve(room);
}

bool FitToEdgesNear(const EdgeMapView& in, double distance, EdgeRefitScratch* scratch, Ellipse* e) {
  const int n = EdgePointsNear(in, *e, distance, &scratch->x, &scratch->y);
  if (n < kMinPoints) return false;
  Arc points;  // RefineEllipse reads only the moments
  points.moments = MomentsOfPoints(scratch->x.data(), scratch->y.data(), 0, n - 1, scratch->x[0], scratch->y[0]);
  const Arc* group[1] = {&points};
  return RefineEllipse(group, 1, e);
}

double RmsDistanceOfEdgesNear(const EdgeMapView& in, const Ellipse& e, double distance, EdgeRefitScratch* scratch) {
  const int n = EdgePointsNear(in, e, distance, &scratch->x, &scratch->y);
  if (n == 0) return 0;
  const double c = std::cos(e.theta), s = std::sin(e.theta);
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double dx = scratch->x[i] - e.cx, dy = scratch->y[i] - e.cy;
    const double u = (dx * c + dy * s) / e.a, v = (dy * c - dx * s) / e.b;  // F = u^2 + v^2 - 1
    const double f = u * u + v * v - 1, gu = 2 * u / e.a, gv = 2 * v / e.b;
    const double g2 = gu * gu + gv * gv;  // 0 only at the centre, which lies near the outline when b <= distance
    sum += g2 > 0 ? f * f / g2 : distance * distance;
  }
  return std::sqrt(sum / n);
}

bool FitToEdgesNearRounds(const EdgeMapView& in, double distance, int rounds, EdgeRefitScratch* scratch, Ellipse* e,
                          long* scanned_pixels) {
  const double frame = static_cast<double>(in.width) * in.height;
  for (int k = 0; k < rounds; ++k) {
    *scanned_pixels += static_cast<long>(std::min(frame, 2 * std::numbers::pi * std::max(e->a, e->b) * (2 * distance + 2)));
    if (!FitToEdgesNear(in, distance, scratch, e)) return false;
  }
  return true;
}

void MinorAxisUp(const Ellipse& e, double* ux, double* uy) {
  *ux = -std::sin(e.theta);
  *uy = std::cos(e.theta);
  if (*uy > 0) {
    *ux = -*ux;
    *uy = -*uy;
  }
}

double CentreRise(const Ellipse& e, const Ellipse& ref) {
  double ux, uy;
  MinorAxisUp(ref, &ux, &uy);
  return (e.cx - ref.cx) * ux + (e.cy - ref.cy) * uy;
}

namespace {
bool StaysClose(const Ellipse& refit, const Ellipse& e) { return FeatureDistance(refit, e) < 0.2 * e.b + 1; }
}  // namespace

bool RefitAlongOutline(const EdgeMapView& in, EdgeRefitScratch* scratch, Ellipse* e, long* scanned_pixels) {
  Ellipse refit = *e;
  if (!FitToEdgesNearRounds(in, kAlongOutlineDistance, 1, scratch, &refit, scanned_pixels) || !StaysClose(refit, *e)) {
    return false;
  }
  *e = refit;
  return true;
}

bool RefitToEdges(const EdgeMapView& in, Ellipse* e, EdgeRefitScratch* scratch, double* share) {
  const double before = share != nullptr && *share >= 0 ? *share : FineEdgeCoverage(in, *e);
  if (share != nullptr) *share = before;
  if (before < kEdgeRefitMinShare) return false;
  Ellipse refit = *e;
  if (!FitToEdgesNear(in, kEdgeRefitDistance, scratch, &refit)) return false;
  if (!StaysClose(refit, *e)) return false;
  // Stops once it cannot reach `before` (returning less); one that reaches it ran to the end.
  const double after = FineEdgeCoverage(in, refit, before - 1.0 / 64);
  if (after < before) return false;
  *e = refit;
  if (share != nullptr) *share = after;
  return true;
}

}  // namespace ellipsekit
