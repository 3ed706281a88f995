// tools/eval/pr_curve.h: hand-computed curves and average precision.
#include <gtest/gtest.h>

#include "tools/eval/pr_curve.h"

namespace {

using ellipsekit::eval::ComputePrCurve;
using ellipsekit::eval::PrCurve;

TEST(PrCurve, AlternatingCorrectAndFalse) {
  // Scores 0.9 correct, 0.8 false, 0.7 correct, 0.6 false; 4 truths. Points (P, R): (1, .25),
  // (.5, .25), (2/3, .5), (.5, .5). Envelope 1, 2/3, 2/3, .5: AP = .25 * 1 + .25 * 2/3 = 5/12.
  const PrCurve c = ComputePrCurve({{0.7, true}, {0.6, false}, {0.9, true}, {0.8, false}}, 4);
  ASSERT_EQ(c.points.size(), 4u);
  EXPECT_DOUBLE_EQ(c.points[0].threshold, 0.9);
  EXPECT_DOUBLE_EQ(c.points[0].precision, 1.0);
  EXPECT_DOUBLE_EQ(c.points[1].precision, 0.5);
  EXPECT_DOUBLE_EQ(c.points[2].precision, 2.0 / 3);
  EXPECT_DOUBLE_EQ(c.points[2].recall, 0.5);
  EXPECT_DOUBLE_EQ(c.points[3].threshold, 0.6);
  EXPECT_DOUBLE_EQ(c.average_precision, 5.0 / 12);
}

TEST(PrCurve, EqualScoresEnterTogether) {
  // A false detection ranked first, then a tie of one correct and one false: (0, 0), (1/3, 1/2).
  const PrCurve c = ComputePrCurve({{0.5, true}, {0.9, false}, {0.5, false}}, 2);
  ASSERT_EQ(c.points.size(), 2u);
  EXPECT_DOUBLE_EQ(c.points[1].precision, 1.0 / 3);
  EXPECT_DOUBLE_EQ(c.points[1].recall, 0.5);
  EXPECT_DOUBLE_EQ(c.average_precision, 0.5 / 3);
}

TEST(PrCurve, EmptyCases) {
  EXPECT_DOUBLE_EQ(ComputePrCurve({}, 3).average_precision, 0);
  EXPECT_DOUBLE_EQ(ComputePrCurve({{1, false}}, 0).average_precision, 0);
  EXPECT_DOUBLE_EQ(ComputePrCurve({{1, true}, {0.5, true}}, 2).average_precision, 1);
}

}  // namespace
