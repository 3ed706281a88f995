#include "fit/validation.h"

#include <cmath>

namespace ellipsekit {

double LengthRatio(const Arc* const* arcs, int count, const Ellipse& e) {
  double sum = 0;
  for (int i = 0; i < count; ++i) sum += arcs[i]->width + arcs[i]->height;
  return sum / (count * (e.a + e.b));
}

double CircumferenceRatio(const Curves& curves, const Arc* const* arcs, int count, const Ellipse& e,
                          InlierRule rule, double threshold) {
  const double c = std::cos(e.theta), s = std::sin(e.theta);
  const double ia2 = 1.0 / (e.a * e.a), ib2 = 1.0 / (e.b * e.b);
  long total = 0, inliers = 0;
  for (int i = 0; i < count; ++i) {
    for (int p = arcs[i]->begin; p <= arcs[i]->end; ++p) {
      const double dx = curves.x[p] - e.cx, dy = curves.y[p] - e.cy;
      const double xo = dx * c + dy * s, yo = dy * c - dx * s;  // eq. 14
      const double f = xo * xo * ia2 + yo * yo * ib2 - 1.0;
      double d = std::abs(f);  // eq. 15
      if (rule == InlierRule::kPixel) {
        const double g = 2.0 * std::hypot(xo * ia2, yo * ib2);
        d = g > 0 ? d / g : HUGE_VAL;
      }
      ++total;
      if (d < threshold) ++inliers;
    }
  }
  return total > 0 ? static_cast<double>(inliers) / static_cast<double>(total) : 0.0;
}

}  // namespace ellipsekit
