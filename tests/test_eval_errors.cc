// eval's error classification (tools/eval/errors.h): each missed truth ellipse and each false
// detection with the other side's ellipse that overlaps it most; near misses (0.5-0.8) counted
// apart; don't-care ellipses never listed.
#include <gtest/gtest.h>

#include <vector>

#include "tools/eval/errors.h"
#include "tools/eval/metrics.h"

namespace ellipsekit::eval {
namespace {

Ellipse E(double cx, double cy, double a, double b) { return Ellipse{cx, cy, a, b, 0}; }

void ExpectUnmatched(const UnmatchedEllipse& u, int index, int nearest, double overlap) {
  EXPECT_EQ(u.index, index);
  EXPECT_EQ(u.nearest, nearest);
  EXPECT_NEAR(u.best_overlap, overlap, 1e-3);
}

TEST(ClassifyErrors, NearMissesAndEllipsesOnNothing) {
  // Truth 0 found exactly; truth 1 only by a flatter ellipse inside it (Jaccard 14 / 20 = 0.7);
  // truth 2 by nothing; detection 2 lies on no truth.
  const std::vector<Ellipse> truth = {E(100, 100, 20, 20), E(300, 100, 20, 20), E(500, 500, 10, 10)};
  const std::vector<Ellipse> dets = {E(100, 100, 20, 20), E(300, 100, 20, 14), E(700, 700, 10, 10)};
  const MatchResult match = MatchEllipses(dets, truth);
  ASSERT_EQ(match.counts, (MatchCounts{3, 3, 1}));
  const ImageErrors errors = ClassifyErrors(dets, truth, match);

  ASSERT_EQ(errors.missed.size(), 2u);
  ExpectUnmatched(errors.missed[0], 1, 1, 0.7);
  ExpectUnmatched(errors.missed[1], 2, -1, 0);
  ASSERT_EQ(errors.false_detections.size(), 2u);
  ExpectUnmatched(errors.false_detections[0], 1, 1, 0.7);
  ExpectUnmatched(errors.false_detections[1], 2, -1, 0);

  ErrorCounts total = CountErrors(errors);
  EXPECT_EQ(total.missed, 2);
  EXPECT_EQ(total.missed_near, 1);
  EXPECT_EQ(total.false_detections, 2);
  EXPECT_EQ(total.false_near, 1);
  // The lists agree with the counts of sec. III-A: missed = truth - correct, false = detected - correct.
  EXPECT_EQ(total.missed, match.counts.truth - match.counts.correct);
  EXPECT_EQ(total.false_detections, match.counts.detected - match.counts.correct);
  total += CountErrors(errors);
  EXPECT_EQ(total.missed_near, 2);
}

TEST(ClassifyErrors, NearestIsTheLargestOverlap) {
  // Two detections on one truth, neither above 0.8: the miss names the closer one.
  const std::vector<Ellipse> truth = {E(0, 0, 20, 20)};
  const std::vector<Ellipse> dets = {E(0, 0, 20, 11), E(0, 0, 20, 15)};
  const ImageErrors errors = ClassifyErrors(dets, truth, MatchEllipses(dets, truth));
  ASSERT_EQ(errors.missed.size(), 1u);
  EXPECT_EQ(errors.missed[0].nearest, 1);
  EXPECT_NEAR(errors.missed[0].best_overlap, 0.75, 1e-3);
  // Both detections are false and near the truth (0.55 and 0.75).
  EXPECT_EQ(CountErrors(errors).false_near, 2);
}

TEST(ClassifyErrors, DontCareEllipsesAreNotErrors) {
  const std::vector<Ellipse> truth = {E(10, 10, 8, 8), E(100, 100, 20, 20)};
  const std::vector<Ellipse> dets = {E(12, 9, 3, 3), E(200, 200, 5, 5)};
  const std::vector<BoundingBox> boxes = {{0, 0, 20, 20}};
  const MatchResult match = MatchEllipses(dets, truth, kOverlapThreshold, boxes);
  const ImageErrors errors = ClassifyErrors(dets, truth, match);
  ASSERT_EQ(errors.missed.size(), 1u);
  EXPECT_EQ(errors.missed[0].index, 1);
  ASSERT_EQ(errors.false_detections.size(), 1u);
  EXPECT_EQ(errors.false_detections[0].index, 1);
}

}  // namespace
}  // namespace ellipsekit::eval
