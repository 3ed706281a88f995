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

// What FindTopOverSide and FindLidInside each ask of the one search inside e below.
struct InsideSearch {
  double max_axis_ratio;  // searched only when e.b <= this * e.a
  double a_scale;         // guesses' a scaled by this (0: as b)
  double min_b, max_b;    // guesses' b scaled by `steps` values in [min_b, max_b]
  int steps;
  bool (*shape)(const Ellipse& found, const Ellipse& e);  // the accepted geometry
  double min_share;       // FineEdgeCoverage the found ellipse must reach
};

// The search inside e (b <= max_axis_ratio a, its minor axis up: -y >= kTopOverSideMinUp): of the
// guesses through e's far point, the best backed (FineEdgeCoverage above kTopOverSideGuessShare)
// refitted to the edges, then accepted when `shape` holds, it reaches min_share and
// StripedShare <= kTopOverSideMaxStriped; *found's score is e's.
bool SearchInside(const EdgeMapView& in, const Ellipse& e, const InsideSearch& search, EdgeRefitScratch* scratch,
                  Ellipse* found, long* scanned_pixels) {
  *scanned_pixels = 0;
  if (e.b > search.max_axis_ratio * e.a) return false;
  double ux, uy;
  MinorAxisUp(e, &ux, &uy);
  if (-uy < kTopOverSideMinUp) return false;
  Ellipse best;
  double best_share = kTopOverSideGuessShare;
  for (int k = 0; k < search.steps; ++k) {
    const double kb = search.min_b + (search.max_b - search.min_b) * k / (search.steps - 1);
    Ellipse g = e;
    g.a *= search.a_scale > 0 ? search.a_scale : kb;
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
  if (!search.shape(best, e)) return false;
  if (FineEdgeCoverage(in, best, search.min_share) < search.min_share) return false;
  if (StripedShare(in, best, kTopOverSideMaxStriped) > kTopOverSideMaxStriped) return false;
  *found = best;
  found->score = e.score;
  return true;
}
}  // namespace

bool IsTopOverSide(const Ellipse& top, const Ellipse& e) {
  const double ka = top.a / e.a, kb = top.b / e.b;
  if (!(kb >= 0.5 && kb <= 0.85 && ka >= 0.8 && ka <= 1.0 && kb <= ka - 0.03)) return false;
  return FarPointsMeet(top, e);
}

bool FindTopOverSide(const EdgeMapView& in, const Ellipse& e, EdgeRefitScratch* scratch, Ellipse* top,
                     long* scanned_pixels) {
  static constexpr InsideSearch kSearch = {kTopOverSideMaxAxisRatio, kTopOverSideA,     kTopOverSideMinB,
                                           kTopOverSideMaxB,         kTopOverSideSteps, IsTopOverSide,
                                           kTopOverSideMinShare};
  return SearchInside(in, e, kSearch, scratch, top, scanned_pixels);
}

bool IsLidInside(const Ellipse& lid, const Ellipse& e) {
  const double ka = lid.a / e.a, kb = lid.b / e.b;
  const double lo = kLidInsideMinScale - 0.03, hi = kLidInsideMaxScale + 0.02;
  if (!(ka >= lo && ka <= hi && kb >= lo && kb <= hi && std::abs(ka - kb) <= 0.06)) return false;
  return FarPointsMeet(lid, e);
}

bool FindLidInside(const EdgeMapView& in, const Ellipse& e, EdgeRefitScratch* scratch, Ellipse* lid,
                   long* scanned_pixels) {
  static constexpr InsideSearch kSearch = {kLidInsideMaxAxisRatio, 0,  kLidInsideMinScale, kLidInsideMaxScale,
                                           kLidInsideSteps,        IsLidInside, kLidInsideMinShare};
  return SearchInside(in, e, kSearch, scratch, lid, scanned_pixels);
}

}  // namespace ellipsekit
