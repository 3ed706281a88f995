#include "tools/eval/pr_curve.h"

#include <algorithm>

namespace ellipsekit::eval {

PrCurve ComputePrCurve(std::vector<ScoredDetection> detections, int truth) {
  std::sort(detections.begin(), detections.end(),
            [](const ScoredDetection& u, const ScoredDetection& v) { return u.score > v.score; });
  PrCurve curve;
  int correct = 0;
  for (std::size_t i = 0; i < detections.size(); ++i) {
    correct += detections[i].correct ? 1 : 0;
    if (i + 1 < detections.size() && detections[i + 1].score == detections[i].score) continue;
    const int kept = static_cast<int>(i + 1);
    curve.points.push_back({detections[i].score, static_cast<double>(correct) / kept,
                            truth > 0 ? static_cast<double>(correct) / truth : 0});
  }
  // Envelope from the right, then the area over each recall step.
  double best = 0, ap = 0, recall_before = 0;
  std::vector<double> envelope(curve.points.size());
  for (std::size_t i = curve.points.size(); i-- > 0;) envelope[i] = best = std::max(best, curve.points[i].precision);
  for (std::size_t i = 0; i < curve.points.size(); ++i) {
    ap += (curve.points[i].recall - recall_before) * envelope[i];
    recall_before = curve.points[i].recall;
  }
  curve.average_precision = ap;
  return curve;
}

}  // namespace ellipsekit::eval
