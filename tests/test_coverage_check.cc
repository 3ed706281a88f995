// The detector's clustering check (runtime/coverage_check.h): the second chance of
// Options::rescue_min_coverage, its floor, and the budget that bounds its work.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "fit/edge_coverage.h"
#include "runtime/coverage_check.h"
#include "tests/stage_test_util.h"

namespace ellipsekit {
namespace {

Candidate PairCandidate(double cx, double cy, double a, double b) {
  Candidate c;
  c.ellipse.cx = cx;
  c.ellipse.cy = cy;
  c.ellipse.a = a;
  c.ellipse.b = b;
  c.ellipse.theta = 0;
  c.arcs[0] = 0;
  c.arcs[1] = 1;  // arcs[2] stays -1: a two-arc candidate, held to pair_min_edge_coverage
  return c;
}

// A bright disk of radius 40 px centred at (80, 60) on a dark frame, through the scalar edge stage.
struct DiskEdges {
  cv::Mat image;
  stage_test::Edges edges;
  EdgeMapView view;
  DiskEdges() : image(120, 160, CV_8UC1, cv::Scalar(40)) {
    cv::circle(image, cv::Point(80, 60), 40, cv::Scalar(200), cv::FILLED, cv::LINE_AA);
    stage_test::ScalarEdges(stage_test::ViewOf(image), Options(), &edges);
    view = {edges.edge_map.data(), image.cols, edges.dx.data(), edges.dy.data(), image.cols, image.cols, image.rows};
  }
};

// A two-arc fit 2.5 px off the disk's outline misses the pair share; refitted to the edges along
// its outline it lies on the disk and passes, and replaces the candidate's ellipse.
TEST(CoverageCheck, ASecondChanceRefitsACandidateOffItsOutline) {
  const DiskEdges disk;
  EdgeRefitScratch scratch;
  scratch.Reserve(disk.image.cols, disk.image.rows);
  Options o;
  o.rescue_min_coverage = 0;  // every failed candidate gets its second chance
  const CoverageCheck check(disk.view, o, &scratch);
  Candidate c = PairCandidate(82.5, 61.0, 41.0, 39.0);
  const double share = EdgeCoverage(disk.view, c.ellipse);
  ASSERT_LT(share, o.pair_min_edge_coverage);
  EXPECT_FALSE(check.Passes(c));
  ASSERT_TRUE(check.PassesRefitted(&c));
  EXPECT_NEAR(c.ellipse.cx, 80, 0.5);
  EXPECT_NEAR(c.ellipse.cy, 60, 0.5);
  EXPECT_NEAR(c.ellipse.a, 40, 1.0);
  EXPECT_NEAR(c.ellipse.b, 40, 1.0);
  EXPECT_TRUE(check.Passes(c));

  // Below the floor: no second chance, the candidate left as it was.
  o.rescue_min_coverage = std::min(1.0, share + 1.0 / 64);
  const CoverageCheck strict(disk.view, o, &scratch);
  Candidate d = PairCandidate(82.5, 61.0, 41.0, 39.0);
  EXPECT_FALSE(strict.PassesRefitted(&d));
  EXPECT_EQ(d.ellipse.cx, 82.5);
  EXPECT_FALSE(strict.BudgetSpent());
}

// Bounded work: the refits' bands may cover two frames' worth of pixels, then no candidate gets a
// second chance and BudgetSpent() says so (the detector reports kCapSecondChance). On an empty
// edge map every refit fails, and each one is charged 2 pi max(a, b) (2 * 2.5 + 2) px.
TEST(CoverageCheck, TheSecondChancesSpendAtMostTwoFramesOfPixels) {
  const int w = 64, h = 48;
  std::vector<std::uint8_t> map(w * h, 0);
  std::vector<std::int16_t> grad(w * h, 0);
  const EdgeMapView view{map.data(), w, grad.data(), grad.data(), w, w, h};
  EdgeRefitScratch scratch;
  scratch.Reserve(w, h);
  Options o;
  o.rescue_min_coverage = 0;
  const CoverageCheck check(view, o, &scratch);
  const double band = 2 * std::numbers::pi * 40 * (2 * kAlongOutlineDistance + 2);  // 1759 px
  const int tries = static_cast<int>(std::ceil(2.0 * w * h / band));                 // 4
  ASSERT_EQ(tries, 4);
  for (int k = 0; k < tries; ++k) {
    EXPECT_FALSE(check.BudgetSpent()) << k;
    Candidate c = PairCandidate(32, 24, 40, 30);
    EXPECT_FALSE(check.PassesRefitted(&c));
  }
  EXPECT_TRUE(check.BudgetSpent());

  o.rescue_min_coverage = 2;  // off: nothing is tried, nothing spent
  const CoverageCheck off(view, o, &scratch);
  for (int k = 0; k < 10; ++k) {
    Candidate c = PairCandidate(32, 24, 40, 30);
    EXPECT_FALSE(off.PassesRefitted(&c));
  }
  EXPECT_FALSE(off.BudgetSpent());
}

}  // namespace
}  // namespace ellipsekit
