// Precision-recall curve and average precision over a score threshold, the convention of
// detection benchmarks (PASCAL VOC's "all points" AP).
//
// Each detection is labelled once, by the dataset's matching at the full detection list
// (metrics.h: Jaccard > 0.8, one-to-one): correct or false. Lowering the threshold past a
// detection's score adds it: recall = correct so far / truth, precision = correct so far /
// detected so far (detections of equal score enter together). AP = the area under the precision
// envelope (precision at recall r taken as the best precision at any recall >= r), summed over
// the recall steps. A detection that a lower threshold would match differently keeps its label:
// re-matching per threshold could only raise the curve.
#pragma once

#include <vector>

namespace ellipsekit::eval {

struct ScoredDetection {
  double score = 0;
  bool correct = false;
};

struct PrPoint {
  double threshold = 0;  // detections with score >= threshold are kept
  double precision = 1, recall = 0;
};

struct PrCurve {
  std::vector<PrPoint> points;  // threshold decreasing, recall non-decreasing
  double average_precision = 0;
};

// truth: ground-truth ellipses of the dataset (the recall denominator; 0 gives AP 0).
PrCurve ComputePrCurve(std::vector<ScoredDetection> detections, int truth);

}  // namespace ellipsekit::eval
