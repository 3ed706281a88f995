// What the errors of one image are (our addition to sec. III-A's counts): each missed truth
// ellipse and each false detection, with the ellipse on the other side that overlaps it most.
// A missed top whose best detection overlaps it by 0.5-0.8 is a near miss (the right object, the
// wrong ellipse: a lid instead of a rim, a shoulder, a fit through the top and the side); one that
// no detection overlaps by 0.5 was never found. The same split for false detections tells
// misplaced ellipses (a near miss seen from the other side) from ellipses on no truth at all.
#pragma once

#include <vector>

#include "ellipsekit/types.h"
#include "tools/eval/metrics.h"

namespace ellipsekit::eval {

inline constexpr double kNearMissOverlap = 0.5;  // Jaccard; below kOverlapThreshold

struct UnmatchedEllipse {
  int index = -1;           // into the truth (a miss) or the detections (a false detection)
  int nearest = -1;         // the other side's ellipse that overlaps it most, -1 when none does
  double best_overlap = 0;  // their Jaccard overlap, 0 when none
};

struct ImageErrors {
  std::vector<UnmatchedEllipse> missed;  // truth ellipses not matched nor ignored, in index order
  std::vector<UnmatchedEllipse> false_detections;  // likewise, detections
};

struct ErrorCounts {
  int missed = 0, missed_near = 0;  // near: best_overlap >= kNearMissOverlap
  int false_detections = 0, false_near = 0;
  ErrorCounts& operator+=(const ErrorCounts& o);
};

// The errors of `match` (MatchEllipses of the same detections and truth). Work: one Jaccard
// overlap per unmatched ellipse and ellipse of the other side whose bounding boxes meet.
ImageErrors ClassifyErrors(const std::vector<Ellipse>& detections, const std::vector<Ellipse>& truth,
                           const MatchResult& match);

ErrorCounts CountErrors(const ImageErrors& errors);

}  // namespace ellipsekit::eval
