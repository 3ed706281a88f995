// Our additions to candidate generation and validation, end to end on drawn ellipses: two-arc
// candidates (Options::pair_candidates) find a small flat top whose upper arcs are too short and
// too straight for T_n and T_O, and the b / a floor (Options::min_axis_ratio) refuses a very flat
// ellipse that the arcs would otherwise give.
#include <gtest/gtest.h>

#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "ellipsekit/ellipsekit.h"

namespace {

using ellipsekit::DetectionResult;
using ellipsekit::Detector;
using ellipsekit::Ellipse;
using ellipsekit::Options;

constexpr double kCx = 100.3, kCy = 80.6, kThetaDeg = 10;

// A bright filled ellipse (semi-axes a, b) on a darker ground, with mild noise and blur.
cv::Mat DrawTop(double a, double b) {
  cv::Mat img(160, 200, CV_8UC1, cv::Scalar(70));
  cv::ellipse(img, cv::Point2f(kCx, kCy), cv::Size2f(a, b), kThetaDeg, 0, 360, cv::Scalar(190), cv::FILLED,
              cv::LINE_AA);
  cv::Mat noise(img.size(), CV_16S), wide;
  cv::RNG rng(3);
  rng.fill(noise, cv::RNG::NORMAL, 0, 3);
  img.convertTo(wide, CV_16S);
  wide += noise;
  wide.convertTo(img, CV_8U);
  cv::GaussianBlur(img, img, cv::Size(3, 3), 0.8);
  return img;
}

std::vector<Ellipse> Detect(const cv::Mat& img, const Options& o) {
  Detector d(o);
  EXPECT_TRUE(d.status().ok()) << d.status().message();
  DetectionResult r;
  EXPECT_TRUE(d.detect({img.data, img.cols, img.rows, static_cast<std::ptrdiff_t>(img.step[0])}, &r).ok());
  return r.ellipses;
}

TEST(DetectorPairs, SmallFlatTopNeedsPairCandidates) {
  const cv::Mat img = DrawTop(16, 6);
  const std::vector<Ellipse> found = Detect(img, Options());
  ASSERT_EQ(found.size(), 1u);
  EXPECT_NEAR(found[0].cx, kCx, 1.0);
  EXPECT_NEAR(found[0].cy, kCy, 1.0);
  EXPECT_NEAR(found[0].a, 16, 1.0);
  EXPECT_NEAR(found[0].b, 6, 1.0);
  Options triplets_only;
  triplets_only.pair_candidates = false;
  EXPECT_TRUE(Detect(img, triplets_only).empty()) << "only two arcs pass T_n and T_O";
}

TEST(DetectorPairs, AxisRatioFloorRefusesVeryFlatEllipses) {
  const cv::Mat img = DrawTop(60, 7);  // b / a 0.12
  EXPECT_TRUE(Detect(img, Options()).empty());
  Options no_floor;
  no_floor.min_axis_ratio = 0;
  const std::vector<Ellipse> found = Detect(img, no_floor);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_LT(found[0].b / found[0].a, Options().min_axis_ratio);
  EXPECT_NEAR(found[0].cx, kCx, 1.0);
}

}  // namespace
