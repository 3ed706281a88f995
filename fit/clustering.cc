#include "fit/clustering.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ellipsekit {

double FeatureDistance(const Ellipse& v, const Ellipse& w) {
  double dr = std::fmod(std::abs(v.theta - w.theta), std::numbers::pi);
  dr = std::min(dr, std::numbers::pi - dr);
  const double dcx = v.cx - w.cx, dcy = v.cy - w.cy, da = v.a - w.a, db = v.b - w.b;
  return std::sqrt(dcx * dcx + dcy * dcy + da * da + db * db + dr * dr);
}

int ClusterCandidates(std::vector<Candidate>* candidates, double threshold) {
  // Best score first; equal scores ordered by the parameters, so the order is total and the
  // result never depends on the sort algorithm.
  std::vector<Candidate>& c = *candidates;
  std::sort(c.begin(), c.end(), [](const Candidate& cx, const Candidate& cy) {
    const Ellipse& x = cx.ellipse;
    const Ellipse& y = cy.ellipse;
    if (x.score != y.score) return x.score > y.score;
    if (x.cx != y.cx) return x.cx < y.cx;
    if (x.cy != y.cy) return x.cy < y.cy;
    if (x.a != y.a) return x.a < y.a;
    if (x.b != y.b) return x.b < y.b;
    return x.theta < y.theta;
  });
  std::size_t kept = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    bool duplicate = false;
    for (std::size_t k = 0; k < kept && !duplicate; ++k) {
      duplicate = FeatureDistance(c[i].ellipse, c[k].ellipse) < threshold;
    }
    if (!duplicate) c[kept++] = c[i];
  }
  return static_cast<int>(kept);
}

}  // namespace ellipsekit
