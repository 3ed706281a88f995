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

// The far points of `inside` and e within 0.08 b_e + 1 px.
bool FarPointsMeet(const Ellipse& inside, const Ellipse& e) {
  double tx, ty, ex, ey;
  FarPoint(inside, &tx, &ty);
  FarPoint(e, &ex, &ey);
  return std::hypot(tx - ex, ty - ey) <= 0.08 * e.b + 1;
}

// The searches inside e (its minor axis up, -y >= kTopOverSideMinUp): of `steps` guesses through
// e's far point, b scaled by values in [min_b, max_b] and a by `a_scale` (0: as b), the best
// backed (FineEdgeCoverage above kTopOverSideGuessShare) refitted to the edges; false when none
// is backed so or the refit fails.
bool BestGuessRefitted(const EdgeMapView& in, const Ellipse& e, double a_scale, double min_b, double max_b, int steps,
                       EdgeRefitScratch* scratch, Ellipse* best, long* scanned_pixels) {
  double ux, uy;
  MinorAxisUp(e, &ux, &uy);
  if (-uy < kTopOverSideMinUp) return false;
  double best_share = kTopOverSideGuessShare;
  for (int k = 0; k < steps; ++k) {
    const double kb = min_b + (max_b - min_b) * k / (steps - 1);
    Ellipse g = e;
    g.a *= a_scale > 0 ? a_scale : kb;
    g.b *= kb;
    g.cx += (e.b - g.b) * ux;  // the far point stays
    g.cy += (e.b - g.b) * uy;
    const double share = FineEdgeCoverage(in, g, best_share);
    if (share > best_share) {
      best_share = share;
      *best = g;
    }
  }
  return best_share > kTopOverSideGuessShare && FitToEdgesNearRounds(in, kBandPx, kRefits, scratch, best, scanned_pixels);
}
}  // namespace

bool IsTopOverSide(const Ellipse& top, const Ellipse& e) {
  const double ka = top.a / e.a, kb = top.b / e.b;
  if (!(kb >= 0.5 && kb <= 0.85 && ka >= 0.8 && ka <= 1.0 && kb <= ka - 0.03)) return false;
  return FarPointsMeet(top, e);
}

bool FindTopOverSide(const EdgeMapView& in, const Ellipse& e, EdgeRefitScratch* scratch, Ellipse* top,
                     long* scanned_pixels) {
  *scanned_pixels = 0;
  if (e.b > kTopOverSideMaxAxisRatio * e.a) return false;
  Ellipse best;
  if (!BestGuessRefitted(in, e, kTopOverSideA, kTopOverSideMinB, kTopOverSideMaxB, kTopOverSideSteps, scratch, &best,
                         scanned_pixels))
    return false;
  if (!IsTopOverSide(best, e)) return false;
  if (FineEdgeCoverage(in, best, kTopOverSideMinShare) < kTopOverSideMinShare) return false;
  if (StripedShare(in, best, kTopOverSideMaxStriped) > kTopOverSideMaxStriped) return false;
  *top = best;
  top->score = e.score;
  return true;
}

bool IsLidInside(const Ellipse& lid, const Ellipse& e) {
  const double ka = lid.a / e.a, kb = lid.b / e.b;
  const double lo = kLidInsideMinScale - 0.03, hi = kLidInsideMaxScale + 0.02;
  if (!(ka >= lo && ka <= hi && kb >= lo && kb <= hi && std::abs(ka - kb) <= 0.06)) return false;
  return FarPointsMeet(lid, e);
}

bool FindLidInside(const EdgeMapView& in, const Ellipse& e, EdgeRefitScratch* scratch, Ellipse* lid,
                   long* scanned_pixels) {
  *scanned_pixels = 0;
  if (e.b > kLidInsideMaxAxisRatio * e.a) return false;
  Ellipse best;
  if (!BestGuessRefitted(in, e, 0, kLidInsideMinScale, kLidInsideMaxScale, kLidInsideSteps, scratch, &best,
                         scanned_pixels))
    return false;
  if (!IsLidInside(best, e)) return false;
  if (FineEdgeCoverage(in, best, kLidInsideMinShare) < kLidInsideMinShare) return false;
  if (StripedShare(in, best, kTopOverSideMaxStriped) > kTopOverSideMaxStriped) return false;
  *lid = best;
  lid->score = e.score;
  return true;
}

}  // namespace ellipsekit
