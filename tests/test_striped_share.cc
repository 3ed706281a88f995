// The stripe test (fit/edge_coverage.h StripedShare, Options::max_striped_share) on drawn
// images: an outline that is one boundary of a pattern of concentric bands (a wooden top's growth
// rings) lies in stripes; the boundary of a plain top, of a ring band 4 px wide, or of the top
// that holds the rings does not. End to end, the rules (Options::max_striped_share, and
// max_nested_striped_share for an ellipse inside another) keep the rings of a drawn wooden top
// out of its detections.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "ellipsekit/detector.h"
#include "fit/edge_coverage.h"

namespace {

using ellipsekit::Ellipse;

constexpr int kW = 240, kH = 200;
constexpr double kCx = 121.3, kCy = 98.6, kTheta = 0.4;

Ellipse At(double a, double b) { return Ellipse{kCx, kCy, a, b, kTheta}; }

// Filled ellipse (a, b) at the test centre, drawn 16x sub-pixel.
void Fill(cv::Mat* image, double a, double b, int grey) {
  constexpr int kShift = 4;
  const auto fixed = [](double v) { return static_cast<int>(std::lround(v * (1 << kShift))); };
  cv::ellipse(*image, cv::Point(fixed(kCx), fixed(kCy)), cv::Size(fixed(a), fixed(b)), kTheta * 180 / CV_PI, 0,
              360, cv::Scalar(grey), cv::FILLED, cv::LINE_AA, kShift);
}

// A wooden top: a plain disc (a, b) = (70, 50) on a darker table, its inside from 60 / 40 inward
// in concentric bands 2.5 px wide (along a), alternately darker and lighter.
cv::Mat WoodenTop() {
  cv::Mat image(kH, kW, CV_8UC1, cv::Scalar(60));
  Fill(&image, 70, 50, 170);
  int k = 0;
  for (double a = 60; a > 8; a -= 2.5, ++k) Fill(&image, a, a * 40 / 60, k % 2 == 0 ? 120 : 170);
  return image;
}

// The frame's gradients as the detector's edge stage makes them (3x3 binomial blur, 3x3 Sobel),
// and an edge map (unused by StripedShare, which reads gradients only).
struct Gradients {
  cv::Mat dx, dy, edges;
  explicit Gradients(const cv::Mat& image) {
    cv::Mat blurred;
    cv::GaussianBlur(image, blurred, cv::Size(3, 3), 0);
    cv::Sobel(blurred, dx, CV_16S, 1, 0, 3);
    cv::Sobel(blurred, dy, CV_16S, 0, 1, 3);
    edges = cv::Mat::zeros(image.size(), CV_8UC1);
  }
  ellipsekit::EdgeMapView View() const {
    return {edges.data, kW, reinterpret_cast<const std::int16_t*>(dx.data), reinterpret_cast<const std::int16_t*>(dy.data),
            kW, kW, kH};
  }
};

TEST(StripedShare, ARingBoundaryLiesInStripesThePlainTopDoesNot) {
  const Gradients g(WoodenTop());
  // Band boundaries at a = 60 - 2.5 k: one in the middle of the pattern.
  EXPECT_GT(ellipsekit::StripedShare(g.View(), At(40, 40.0 * 40 / 60)), 0.85);
  // The top's own outline: the table outside, nothing within 2-5 px inside but a same-signed
  // step (the disc is lighter than the table and than the first dark band alike).
  EXPECT_LT(ellipsekit::StripedShare(g.View(), At(70, 50)), 0.1);
}

TEST(StripedShare, ARingBandOrAPlainStepIsNotAStripe) {
  cv::Mat step(kH, kW, CV_8UC1, cv::Scalar(60));
  Fill(&step, 60, 40, 170);
  EXPECT_LT(ellipsekit::StripedShare(Gradients(step).View(), At(60, 40)), 0.1);
  // A ring band 4 px wide (a calibration ring): its outer edge has the opposite edge inside only.
  cv::Mat ring(kH, kW, CV_8UC1, cv::Scalar(200));
  Fill(&ring, 60, 40, 40);
  Fill(&ring, 56, 36, 200);
  const Gradients g(ring);
  EXPECT_LT(ellipsekit::StripedShare(g.View(), At(60, 40)), 0.1);
  EXPECT_LT(ellipsekit::StripedShare(g.View(), At(56, 36)), 0.1);
  // No gradient anywhere: nothing backed, share 0.
  const cv::Mat flat(kH, kW, CV_8UC1, cv::Scalar(90));
  EXPECT_EQ(ellipsekit::StripedShare(Gradients(flat).View(), At(60, 40)), 0);
}

TEST(StripedShare, FarOrDegenerateEllipsesReadNothing) {
  const Gradients g(WoodenTop());
  EXPECT_EQ(ellipsekit::StripedShare(g.View(), Ellipse{1e300, -1e300, 40, 30, 0.2}), 0);
  EXPECT_EQ(ellipsekit::StripedShare(g.View(), Ellipse{kCx, kCy, 1e300, 1e300, 0.2}), 0);
  EXPECT_EQ(ellipsekit::StripedShare(g.View(), Ellipse{kCx, kCy, 0, 0, 0}), 0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(ellipsekit::StripedShare(g.View(), Ellipse{nan, kCy, 40, 30, 0.2}), 0);
}

// True when e lies inside the wooden top, clearly smaller than it (a ring, not the top).
bool IsRing(const Ellipse& e) {
  return std::hypot(e.cx - kCx, e.cy - kCy) < 20 && e.a < 64;
}

TEST(StripedShare, TheRuleKeepsTheRingsOfAWoodenTopOut) {
  const cv::Mat image = WoodenTop();
  const ellipsekit::ImageView view{image.data, image.cols, image.rows, static_cast<std::ptrdiff_t>(image.step)};
  auto rings_found = [&](double max_striped_share, double max_nested_striped_share, bool* top_found) {
    ellipsekit::Options options;
    options.max_striped_share = max_striped_share;
    options.max_nested_striped_share = max_nested_striped_share;
    ellipsekit::Detector detector(options);
    ellipsekit::DetectionResult result;
    EXPECT_TRUE(detector.detect(view, &result).ok());
    int rings = 0;
    *top_found = false;
    for (const Ellipse& e : result.ellipses) {
      rings += IsRing(e);
      *top_found = *top_found || (std::abs(e.a - 70) < 2 && std::abs(e.b - 50) < 2 && std::hypot(e.cx - kCx, e.cy - kCy) < 2);
    }
    return rings;
  };
  const ellipsekit::Options defaults;
  bool top_found_without = false, top_found_with = false, top_found_nested = false;
  // Without the rules the detector reports rings (so the drawing is a fair test of them) ...
  EXPECT_GE(rings_found(1.0, 1.0, &top_found_without), 1);
  // ... with them, none, and the top itself stays; the rings lie inside the detected top, so the
  // rule for nested ellipses alone removes them too.
  EXPECT_EQ(rings_found(defaults.max_striped_share, defaults.max_nested_striped_share, &top_found_with), 0);
  EXPECT_TRUE(top_found_with);
  EXPECT_EQ(rings_found(1.0, defaults.max_nested_striped_share, &top_found_nested), 0);
  EXPECT_TRUE(top_found_nested);
}

}  // namespace
