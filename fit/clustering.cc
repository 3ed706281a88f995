#include "fit/clustering.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ellipsekit {

namespace {
constexpr double kConcentric = 0.2;  // centres closer than this * b count as nested
}

double FeatureDistance(const Ellipse& v, const Ellipse& w) {
  double dr = std::fmod(std::abs(v.theta - w.theta), std::numbers::pi);
  dr = std::min(dr, std::numbers::pi - dr);
  const double dcx = v.cx - w.cx, dcy = v.cy - w.cy, da = v.a - w.a, db = v.b - w.b;
  return std::sqrt(dcx * dcx + dcy * dcy + da * da + db * db + dr * dr);
}

bool SameEllipse(const Ellipse& v, const Ellipse& w, const Options& options) {
  if (options.cluster_rule == ClusterRule::kFeatureDistance) {
    return FeatureDistance(v, w) < options.cluster_distance;
  }
  const double t = options.cluster_relative;
  if (std::hypot(v.cx - w.cx, v.cy - w.cy) > t * std::min(v.b, w.b)) return false;
  if (std::abs(v.a - w.a) > t * std::max(v.a, w.a)) return false;
  if (std::abs(v.b - w.b) > t * std::max(v.b, w.b)) return false;
  const bool round = v.b > 0.9 * v.a && w.b > 0.9 * w.a;  // orientation means little
  if (round) return true;
  double dr = std::fmod(std::abs(v.theta - w.theta), std::numbers::pi);
  dr = std::min(dr, std::numbers::pi - dr);
  return dr <= t;
}

int ClusterCandidates(std::vector<Candidate>* candidates, const Options& options) {
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
    std::size_t k = 0;
    while (k < kept && !SameEllipse(c[i].ellipse, c[k].ellipse, options)) ++k;
    if (k == kept) {
      c[kept++] = c[i];
      continue;
    }
    // Nested rims (a can's outer rim and its inner lip) fall into one cluster; when their scores
    // are within the margin, the outer one — the object's boundary — represents the cluster.
    const Ellipse& e = c[i].ellipse;
    const Ellipse& ref = c[k].ellipse;
    if (e.score >= ref.score - options.cluster_outer_margin && e.a + e.b > ref.a + ref.b &&
        std::hypot(e.cx - ref.cx, e.cy - ref.cy) < kConcentric * ref.b) {
      const double best = ref.score;
      c[k] = c[i];
      c[k].ellipse.score = best;
    }
  }
  return static_cast<int>(kept);
}

}  // namespace ellipsekit
