#include "tools/eval/metrics.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ellipsekit::eval {
namespace {

bool Inside(const BoundingBox& box, double x, double y) {
  return x >= box.x0 && x <= box.x1 && y >= box.y0 && y <= box.y1;
}

bool InAny(const std::vector<BoundingBox>& boxes, const Ellipse& e) {
  for (const BoundingBox& box : boxes) {
    if (Inside(box, e.cx, e.cy)) return true;
  }
  return false;
}

struct Edge {
  int detection, truth;
  double overlap;
};

// Phi <= min(area)/max(area), so a pair whose area ratio is at most the threshold can never
// count; skipping it saves the polygon work for most pairs.
bool MayExceed(const Ellipse& d, const Ellipse& g, double threshold) {
  const double ad = d.a * d.b, ag = g.a * g.b;
  if (!(ad > 0) || !(ag > 0)) return false;
  return std::min(ad, ag) / std::max(ad, ag) > threshold;
}

class Matcher {
 public:
  Matcher(int num_detections, int num_truth, std::vector<std::vector<Edge>> adjacency)
      : adj_(std::move(adjacency)), truth_of_(num_detections, -1), det_of_(num_truth, -1) {}

  void Greedy(std::vector<Edge> edges) {
    std::stable_sort(edges.begin(), edges.end(), [](const Edge& l, const Edge& r) {
      if (l.overlap != r.overlap) return l.overlap > r.overlap;
      if (l.detection != r.detection) return l.detection < r.detection;
      return l.truth < r.truth;
    });
    for (const Edge& e : edges) {
      if (truth_of_[e.detection] < 0 && det_of_[e.truth] < 0) Assign(e.detection, e.truth);
    }
  }

  void Augment() {
    for (int d = 0; d < static_cast<int>(truth_of_.size()); ++d) {
      if (truth_of_[d] >= 0 || adj_[d].empty()) continue;
      std::vector<char> visited(det_of_.size(), 0);
      TryAugment(d, &visited);
    }
  }

  const std::vector<int>& truth_of() const { return truth_of_; }
  const std::vector<int>& det_of() const { return det_of_; }

 private:
  void Assign(int d, int t) {
    truth_of_[d] = t;
    det_of_[t] = d;
  }
  bool TryAugment(int d, std::vector<char>* visited) {
    for (const Edge& e : adj_[d]) {
      if ((*visited)[e.truth]) continue;
      (*visited)[e.truth] = 1;
      if (det_of_[e.truth] < 0 || TryAugment(det_of_[e.truth], visited)) {
        Assign(d, e.truth);
        return true;
      }
    }
    return false;
  }

  std::vector<std::vector<Edge>> adj_;  // per detection, decreasing overlap
  std::vector<int> truth_of_, det_of_;
};

}  // namespace

double Precision(const MatchCounts& c) {
  return c.detected > 0 ? static_cast<double>(c.correct) / c.detected : 1.0;
}

double Recall(const MatchCounts& c) {
  return c.truth > 0 ? static_cast<double>(c.correct) / c.truth : 1.0;
}

double FMeasure(double precision, double recall) {
  const double sum = precision + recall;
  return sum > 0 ? 2 * precision * recall / sum : 0.0;
}

double FMeasure(const MatchCounts& c) { return FMeasure(Precision(c), Recall(c)); }

MatchResult MatchEllipses(const std::vector<Ellipse>& detections, const std::vector<Ellipse>& truth,
                          double threshold, const std::vector<BoundingBox>& dont_care) {
  const int nd = static_cast<int>(detections.size());
  const int nt = static_cast<int>(truth.size());
  MatchResult r;
  r.truth_ignored.assign(nt, false);
  r.detection_ignored.assign(nd, false);
  for (int t = 0; t < nt; ++t) r.truth_ignored[t] = InAny(dont_care, truth[t]);

  std::vector<Edge> edges;
  std::vector<std::vector<Edge>> adjacency(nd);
  for (int d = 0; d < nd; ++d) {
    for (int t = 0; t < nt; ++t) {
      if (r.truth_ignored[t] || !MayExceed(detections[d], truth[t], threshold)) continue;
      const double phi = EllipseJaccard(detections[d], truth[t]);
      if (phi > threshold) {
        edges.push_back({d, t, phi});
        adjacency[d].push_back({d, t, phi});
      }
    }
    std::stable_sort(adjacency[d].begin(), adjacency[d].end(),
                     [](const Edge& l, const Edge& r) { return l.overlap > r.overlap; });
  }

  Matcher matcher(nd, nt, adjacency);
  matcher.Greedy(edges);
  matcher.Augment();
  r.truth_of_detection = matcher.truth_of();
  r.detection_of_truth = matcher.det_of();

  for (int d = 0; d < nd; ++d) {
    const int t = r.truth_of_detection[d];
    if (t >= 0) {
      double phi = 0;
      for (const Edge& e : adjacency[d]) {
        if (e.truth == t) phi = e.overlap;
      }
      r.pairs.push_back({d, t, phi});
    } else if (InAny(dont_care, detections[d])) {
      r.detection_ignored[d] = true;
    }
  }
  for (int t = 0; t < nt; ++t) r.counts.truth += r.truth_ignored[t] ? 0 : 1;
  for (int d = 0; d < nd; ++d) r.counts.detected += r.detection_ignored[d] ? 0 : 1;
  r.counts.correct = static_cast<int>(r.pairs.size());
  return r;
}

}  // namespace ellipsekit::eval
