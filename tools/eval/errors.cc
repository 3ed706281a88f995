#include "tools/eval/errors.h"

#include "tools/eval/overlap.h"

namespace ellipsekit::eval {

namespace {

// For each unmatched, not ignored ellipse of `side`, the ellipse of `other` overlapping it most
// (ties: the lower index).
std::vector<UnmatchedEllipse> Unmatched(const std::vector<Ellipse>& side, const std::vector<int>& partner,
                                        const std::vector<bool>& ignored, const std::vector<Ellipse>& other) {
  std::vector<BoundingBox> other_boxes;
  other_boxes.reserve(other.size());
  for (const Ellipse& o : other) other_boxes.push_back(EllipseBounds(o));
  std::vector<UnmatchedEllipse> out;
  for (std::size_t i = 0; i < side.size(); ++i) {
    if (partner[i] >= 0 || (i < ignored.size() && ignored[i])) continue;
    UnmatchedEllipse u;
    u.index = static_cast<int>(i);
    const BoundingBox box = EllipseBounds(side[i]);
    for (std::size_t j = 0; j < other.size(); ++j) {
      if (!box.Intersects(other_boxes[j])) continue;
      const double overlap = EllipseJaccard(side[i], other[j]);
      if (overlap > u.best_overlap) {
        u.best_overlap = overlap;
        u.nearest = static_cast<int>(j);
      }
    }
    out.push_back(u);
  }
  return out;
}

}  // namespace

ErrorCounts& ErrorCounts::operator+=(const ErrorCounts& o) {
  missed += o.missed;
  missed_near += o.missed_near;
  false_detections += o.false_detections;
  false_near += o.false_near;
  return *this;
}

ImageErrors ClassifyErrors(const std::vector<Ellipse>& detections, const std::vector<Ellipse>& truth,
                           const MatchResult& match) {
  ImageErrors e;
  e.missed = Unmatched(truth, match.detection_of_truth, match.truth_ignored, detections);
  e.false_detections = Unmatched(detections, match.truth_of_detection, match.detection_ignored, truth);
  return e;
}

ErrorCounts CountErrors(const ImageErrors& errors) {
  ErrorCounts c;
  for (const UnmatchedEllipse& u : errors.missed) {
    ++c.missed;
    c.missed_near += u.best_overlap >= kNearMissOverlap;
  }
  for (const UnmatchedEllipse& u : errors.false_detections) {
    ++c.false_detections;
    c.false_near += u.best_overlap >= kNearMissOverlap;
  }
  return c;
}

}  // namespace ellipsekit::eval
