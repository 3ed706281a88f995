#include "fit/recessed_rim.h"

#include <cmath>

#include "fit/edge_coverage.h"

namespace ellipsekit {

namespace {
constexpr int kRefits = 3;
constexpr double kBandPx = 2.0;  // FitToEdgesNear's distance for each refit
}  // namespace

bool IsRecessedRimOf(const Ellipse& rim, const Ellipse& lid) {
  const double c = std::cos(lid.theta), s = std::sin(lid.theta);
  const double up = CentreRise(rim, lid);
  const double across = std::abs((rim.cx - lid.cx) * c + (rim.cy - lid.cy) * s);
  const double ka = rim.a / lid.a, kb = rim.b / lid.b;
  return up >= -0.05 * lid.b && up <= 0.35 * lid.b && across <= 0.15 * lid.b && ka >= 1.03 && ka <= 1.4 &&
         kb >= 1.05 && kb <= 1.55 && kb >= ka - 0.02;
}

bool FindRecessedRim(const EdgeMapView& in, const Ellipse& lid, EdgeRefitScratch* scratch, Ellipse* rim,
                     long* scanned_pixels) {
  *scanned_pixels = 0;
  double ux, uy;
  MinorAxisUp(lid, &ux, &uy);
  Ellipse g = lid;
  g.cx += kRecessedRimUp * lid.b * ux;
  g.cy += kRecessedRimUp * lid.b * uy;
  g.a *= kRecessedRimA;
  g.b *= kRecessedRimB;
  if (FineEdgeCoverage(in, g, kRecessedRimGuessShare) <= kRecessedRimGuessShare) return false;
  if (!FitToEdgesNearRounds(in, kBandPx, kRefits, scratch, &g, scanned_pixels)) return false;
  if (!IsRecessedRimOf(g, lid)) return false;
  if (FineEdgeCoverage(in, g, kRecessedRimMinShare) < kRecessedRimMinShare) return false;
  *rim = g;
  rim->score = lid.score;
  return true;
}

}  // namespace ellipsekit
