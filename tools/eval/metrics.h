// Scoring detections against ground truth (Dong et al. 2018, sec. III-A, eqs. 18-19).
//
// A detection d and a ground-truth ellipse g may be paired when their overlap ratio
// Phi = Jaccard(d, g) is strictly greater than the threshold (Phi_0 = 0.8). Each ground truth
// is paired with at most one detection and each detection with at most one ground truth; the
// pairing has maximum cardinality, so `correct` is the largest number of simultaneous correct
// detections. It is deterministic: pairs are first taken greedily in decreasing Phi order
// (ties: lower detection index, then lower truth index), then augmenting paths (Kuhn's
// algorithm, detections in index order, candidate truths in decreasing Phi order) raise the
// count to the maximum where the greedy choice fell short (rare: it needs one detection above
// the threshold against two ground truths).
//
// Precision = correct / detected, Recall = correct / truth, F = 2PR / (P + R), with the
// empty cases defined as: P = 1 when nothing was detected (no false claim was made), R = 1
// when there is no ground truth (nothing was missed), F = 0 when P + R = 0. Counts are summed
// over a dataset before the ratios are taken (micro average).
#pragma once

#include <vector>

#include "ellipsekit/types.h"
#include "tools/eval/overlap.h"

namespace ellipsekit::eval {

inline constexpr double kOverlapThreshold = 0.8;  // Phi_0, sec. III-A

struct MatchCounts {
  int detected = 0;  // N of eq. 18 (detections not ignored as don't-care)
  int truth = 0;     // M of eq. 18 (ground truth not in a don't-care box)
  int correct = 0;   // Omega of eq. 18

  MatchCounts& operator+=(const MatchCounts& o) {
    detected += o.detected;
    truth += o.truth;
    correct += o.correct;
    return *this;
  }
  friend MatchCounts operator+(MatchCounts l, const MatchCounts& r) { return l += r; }
  friend bool operator==(const MatchCounts&, const MatchCounts&) = default;
};

double Precision(const MatchCounts& c);
double Recall(const MatchCounts& c);
double FMeasure(const MatchCounts& c);
double FMeasure(double precision, double recall);

struct MatchPair {
  int detection = -1;  // index into the detections
  int truth = -1;      // index into the ground truth
  double overlap = 0;  // Phi
};

struct MatchResult {
  MatchCounts counts;
  std::vector<MatchPair> pairs;           // sorted by detection index
  std::vector<int> truth_of_detection;    // per detection: matched truth index or -1
  std::vector<int> detection_of_truth;    // per truth: matched detection index or -1
  std::vector<bool> detection_ignored;    // per detection: unmatched and in a don't-care box
  std::vector<bool> truth_ignored;        // per truth: centre in a don't-care box
};

// Pairs detections with ground truth in one image. `dont_care`: boxes of this image (dataset.h).
MatchResult MatchEllipses(const std::vector<Ellipse>& detections, const std::vector<Ellipse>& truth,
                          double threshold = kOverlapThreshold,
                          const std::vector<BoundingBox>& dont_care = {});

}  // namespace ellipsekit::eval
