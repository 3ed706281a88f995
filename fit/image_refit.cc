#include "fit/image_refit.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "fit/arc.h"
#include "fit/clustering.h"
#include "fit/conic_refine.h"
#include "fit/point_moments.h"

namespace ellipsekit {

namespace {

constexpr int kMinPoints = 12;
constexpr int kMinSamples = 32;
constexpr double kMinStep = 4;  // gray levels: a weaker step is no rim
// A normal's step counts when it is at least this share of the median step around the outline
// (a rim's contrast varies along it; texture beside it is weaker than the rim).
constexpr double kMinShareOfMedian = 0.25;
// Profile points per side of the outline at the first round's reach (1.5 x 2^L px): 6 steps
// of 2^L / 4 px (0.5 px at L = 1). The second round reaches 2 steps.
constexpr int kFirstReachSteps = 6;
constexpr int kSecondReachSteps = 2;
constexpr int kMaxProfile = 2 * kFirstReachSteps + 1;
// The brightness difference spans 2 h = 2^L px (h = 2 steps): the level's own pixel.
constexpr int kSpanSteps = 2;
constexpr int kSideLines = 1;  // lines each side of the normal's own, kSpanSteps steps (2^(L-1) px) apart

// Bilinear brightness at (x, y); the caller keeps (x, y) inside [0, w - 1] x [0, h - 1].
double Bilinear(const ImageView& im, double x, double y) {
  const int x0 = std::min(static_cast<int>(x), im.width - 2), y0 = std::min(static_cast<int>(y), im.height - 2);
  const double fx = x - x0, fy = y - y0;
  const std::uint8_t* r0 = im.data + y0 * im.stride + x0;
  const std::uint8_t* r1 = r0 + im.stride;
  const double top = r0[0] + fx * (r0[1] - r0[0]), bottom = r1[0] + fx * (r1[1] - r1[0]);
  return top + fy * (bottom - top);
}

struct RimPoints {
  double x[kImageRefitSamples], y[kImageRefitSamples];
  int found = 0;  // points kept
};

// One round: along `samples` normals of e, the strongest step within reach_steps steps of
// `step_px` px on either side of the outline.
void FindRimPoints(const ImageView& im, const Ellipse& e, int samples, double step_px, int reach_steps,
                   RimPoints* out) {
  const double c = std::cos(e.theta), s = std::sin(e.theta);
  const double reach = (reach_steps + 2 * kSpanSteps) * step_px;  // outermost read, side lines included
  const int profile = 2 * reach_steps + 1;
  out->found = 0;
  double px[kImageRefitSamples], py[kImageRefitSamples], mag[kImageRefitSamples];
  for (int i = 0; i < samples; ++i) {
    const double t = 2 * std::numbers::pi * i / samples, ct = std::cos(t), st = std::sin(t);
    const double x = e.cx + e.a * ct * c - e.b * st * s, y = e.cy + e.a * ct * s + e.b * st * c;
    double nx = ct / e.a * c - st / e.b * s, ny = ct / e.a * s + st / e.b * c;  // outward normal
    const double nn = std::hypot(nx, ny);
    nx /= nn;
    ny /= nn;
    const double tx = -ny, ty = nx;
    if (x - reach < 0 || y - reach < 0 || x + reach > im.width - 1 || y + reach > im.height - 1) continue;
    // d[k]: brightness at offset (k - reach_steps + kSpanSteps) minus at (k - reach_steps - kSpanSteps)
    // steps along the normal, summed over 2 kSideLines + 1 parallel lines kSpanSteps steps apart.
    double d[kMaxProfile];
    for (int k = 0; k < profile; ++k) d[k] = 0;
    for (int line = -kSideLines; line <= kSideLines; ++line) {
      const double ox = x + line * kSpanSteps * step_px * tx, oy = y + line * kSpanSteps * step_px * ty;
      double v[kMaxProfile + 2 * kSpanSteps];
      for (int j = 0; j < profile + 2 * kSpanSteps; ++j) {
        const double o = (j - reach_steps - kSpanSteps) * step_px;
        v[j] = Bilinear(im, ox + o * nx, oy + o * ny);
      }
      for (int k = 0; k < profile; ++k) d[k] += v[k + 2 * kSpanSteps] - v[k];
    }
    // The strongest local maximum of |d| inside the profile, nearer ones preferred a little.
    int best = -1;
    double best_w = 0;
    for (int k = 1; k + 1 < profile; ++k) {
      const double m = std::abs(d[k]);
      if (m < std::abs(d[k - 1]) || m < std::abs(d[k + 1])) continue;
      const double w = m * (1 - 0.25 * std::abs(k - reach_steps) / reach_steps);
      if (w > best_w) {
        best_w = w;
        best = k;
      }
    }
    if (best < 0) continue;
    const double m0 = std::abs(d[best - 1]), m1 = std::abs(d[best]), m2 = std::abs(d[best + 1]);
    const double curv = m0 - 2 * m1 + m2;
    const double frac = curv < 0 ? std::clamp(0.5 * (m0 - m2) / curv, -0.5, 0.5) : 0.0;
    const double o = (best - reach_steps + frac) * step_px;
    const int n = out->found;
    px[n] = x + o * nx;
    py[n] = y + o * ny;
    mag[n] = m1 / (2 * kSideLines + 1);
    ++out->found;
  }
  // Keep the steps that are a rim's: above kMinStep and kMinShareOfMedian of the median.
  const int n = out->found;
  if (n == 0) return;
  double sorted[kImageRefitSamples];
  std::copy(mag, mag + n, sorted);
  std::nth_element(sorted, sorted + n / 2, sorted + n);
  const double floor = std::max(kMinStep, kMinShareOfMedian * sorted[n / 2]);
  int kept = 0;
  for (int i = 0; i < n; ++i) {
    if (mag[i] < floor) continue;
    out->x[kept] = px[i];
    out->y[kept] = py[i];
    ++kept;
  }
  out->found = kept;
}

// The direct fit of the round's points; false when they give no ellipse.
bool FitRimPoints(const RimPoints& p, Ellipse* e) {
  if (p.found < kMinPoints) return false;
  Arc points;  // RefineEllipse reads only the moments
  points.moments = MomentsOfPoints(p.x, p.y, 0, p.found - 1, std::round(p.x[0]), std::round(p.y[0]));
  const Arc* group[1] = {&points};
  return RefineEllipse(group, 1, e);
}

}  // namespace

bool RefitToImage(const ImageView& image, int level, Ellipse* e) {
  if (level < 1 || image.width < 2 || image.height < 2 || !(e->b > 0) || !std::isfinite(e->a) ||
      !std::isfinite(e->cx) || !std::isfinite(e->cy) || !std::isfinite(e->theta))
    return false;
  const double scale = static_cast<double>(1 << level);
  const double step_px = scale / 4;
  const double perimeter = std::numbers::pi * (3 * (e->a + e->b) - std::sqrt((3 * e->a + e->b) * (e->a + 3 * e->b)));
  const int samples = static_cast<int>(std::clamp(perimeter / 8, double{kMinSamples}, double{kImageRefitSamples}));
  const int needed = std::max(kMinPoints, static_cast<int>(std::ceil(kImageRefitMinShare * samples)));
  RimPoints points;
  Ellipse refit = *e;
  for (const int reach_steps : {kFirstReachSteps, kSecondReachSteps}) {
    FindRimPoints(image, refit, samples, step_px, reach_steps, &points);
    if (points.found < needed || !FitRimPoints(points, &refit)) return false;
  }
  if (!(FeatureDistance(refit, *e) < 0.2 * e->b + scale)) return false;
  *e = refit;
  return true;
}

}  // namespace ellipsekit
