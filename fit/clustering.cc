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

void ClusterCandidates(std::vector<Ellipse>* candidates, double threshold, std::vector<Ellipse>* out) {
  // Best score first; equal scores ordered by the parameters, so the order is total and the
  // result never depends on the sort algorithm.
  std::vector<Ellipse>& c = *candidates;
  std::sort(c.begin(), c.end(), [](const Ellipse& x, const Ellipse& y) {
    if (x.score != y.score) return x.score > y.score;
    if (x.cx != y.cx) return x.cx < y.cx;
    if (x.cy != y.cy) return x.cy < y.cy;
    if (x.a != y.a) return x.a < y.a;
    if (x.b != y.b) return x.b < y.b;
    return x.theta < y.theta;
  });
  const std::size_t first = out->size();
  for (const Ellipse& e : c) {
    bool duplicate = false;
    for (std::size_t k = first; k < out->size() && !duplicate; ++k) {
      duplicate = FeatureDistance(e, (*out)[k]) < threshold;
    }
    if (!duplicate) out->push_back(e);
  }
}

}  // namespace ellipsekit
