#include "fit/validation.h"

#include <algorithm>
#include <cmath>

namespace ellipsekit {

double LengthRatio(const Arc* const* arcs, int count, const Ellipse& e) {
  double sum = 0;
  for (int i = 0; i < count; ++i) sum += arcs[i]->width + arcs[i]->height;
  return sum / (count * (e.a + e.b));
}

double CircumferenceRatio(const Curves& curves, const Arc* const* arcs, int count, const Ellipse& e,
                          InlierRule rule, double threshold, double min_ratio) {
  const double c = std::cos(e.theta), s = std::sin(e.theta);
  const double ia2 = 1.0 / (e.a * e.a), ib2 = 1.0 / (e.b * e.b);
  // kPixel: d = |f| / g with g = 2 |(xo / a^2, yo / b^2)| (eq. 15's first-order distance), tested
  // as f^2 < 4 T_d^2 |(..)|^2: the same decision without a root or a division per point
  // (g = 0 fails it, as d = inf does).
  const double four_t2 = 4.0 * threshold * threshold;
  long total = 0;
  for (int i = 0; i < count; ++i) total += arcs[i]->end - arcs[i]->begin + 1;
  if (total == 0) return 0.0;
  const double n = static_cast<double>(total);
  long outliers = 0;
  // psi <= (total - outliers) / total, and so is its rounded value (division by the same n is
  // monotone): once that is <= min_ratio, psi > min_ratio cannot hold. Checked before every block
  // of kBlock points (not by a modulo per point), so a bad fit stops after a tenth or so of its
  // points (min_ratio 0.9) instead of after its first arc; the value returned for a passing fit is
  // unchanged.
  constexpr int kBlock = 32;
  for (int i = 0; i < count; ++i) {
    for (int from = arcs[i]->begin; from <= arcs[i]->end; from += kBlock) {
      if (static_cast<double>(total - outliers) / n <= min_ratio) return static_cast<double>(total - outliers) / n;
      const int to = std::min(from + kBlock - 1, arcs[i]->end);
      for (int p = from; p <= to; ++p) {
        const double dx = curves.x[p] - e.cx, dy = curves.y[p] - e.cy;
        const double xo = dx * c + dy * s, yo = dy * c - dx * s;  // eq. 14
        const double f = xo * xo * ia2 + yo * yo * ib2 - 1.0;
        bool inlier;
        if (rule == InlierRule::kPixel) {
          const double u = xo * ia2, v = yo * ib2;
          inlier = f * f < four_t2 * (u * u + v * v);
        } else {
          inlier = std::abs(f) < threshold;  // eq. 15
        }
        outliers += !inlier;
      }
    }
  }
  return static_cast<double>(total - outliers) / n;
}

}  // namespace ellipsekit
