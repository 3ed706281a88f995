#include "fit/top_over_side.h"

#include <cmath>

#include "fit/edge_coverage.h"

namespace ellipsekit {

namespace {
constexpr int kRefits = 3;
constexpr double kBandPx = 2.0;  // FitToEdgesNear's distance for each refit

// e's far point: the end of its minor axis that lies up in the image.
void FarPoint(const Ellipse& e, double* x, double* y) {
  double ux, uy;
  MinorAxisUp(e, &ux, &uy);
  *x = e.cx + e.b * ux;
  *y = e.cy + e.b * uy;
}
}  // namespace

bool IsTopOverSide(const Ellipse& top, const Ellipse& e) {
  const double ka = top.a / e.a, kb = top.b / e.b;
  if (!(kb >= 0.5 && kb <= 0.85 && ka >= 0.8 && ka <= 1.0 && kb <= ka - 0.03)) return false;
  double tx, ty, ex, ey;
  FarPoint(top, &tx, &ty);
  FarPoint(e, &ex, &ey);
  return std::hypot(tx - ex, ty - ey) <= 0.08 * e.b + 1;
}

bool FindTopOverSide(const EdgeMapView& in, const Ellipse& e, EdgeRefitScratch* scratch, Ellipse* top,
                     long* scanned_pixels) {
  *scanned_pixels = 0;
  if (e.b > kTopOverSideMaxAxisRatio * e.a) return false;
  double ux, uy;
  MinorAxisUp(e, &ux, &uy);
  if (-uy < kTopOverSideMinUp) return false;
  Ellipse best = e;
  double best_share = kTopOverSideGuessShare;
  for (int k = 0; k < kTopOverSideSteps; ++k) {
    const double kb = kTopOverSideMinB + (kTopOverSideMaxB - kTopOverSideMinB) * k / (kTopOverSideSteps - 1);
    Ellipse g = e;
    g.a *= kTopOverSideA;
    g.b *= kb;
    g.cx += (e.b - g.b) * ux;  // the far point stays
    g.cy += (e.b - g.b) * uy;
    const double share = FineEdgeCoverage(in, g, best_share);
    if (share > best_share) {
      best_share = share;
      best = g;
    }
  }
  if (best_share <= kTopOverSideGuessShare) return false;
  if (!FitToEdgesNearRounds(in, kBandPx, kRefits, scratch, &best, scanned_pixels)) return false;
  if (!IsTopOverSide(best, e)) return false;
  if (FineEdgeCoverage(in, best, kTopOverSideMinShare) < kTopOverSideMinShare) return false;
  if (StripedShare(in, best, kTopOverSideMaxStriped) > kTopOverSideMaxStriped) return false;
  *top = best;
  top->score = e.score;
  return true;
}

}  // namespace ellipsekit
