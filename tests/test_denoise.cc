// The noise estimate (kernels/noise_sigma.h) and the smoothing it decides
// (Options::denoise_min_sigma): the estimate on frames whose noise is known, and what the extra
// smoothing buys on generated scenes with strong sensor noise added.
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "ellipsekit/detector.h"
#include "kernels/noise_sigma.h"
#include "tests/ellipse_test_util.h"
#include "tools/eval/metrics.h"
#include "tools/eval/sensor_noise.h"
#include "tools/scenes/scene_generator.h"

namespace {

double Sigma(const cv::Mat& m) {
  return ellipsekit::scalar::NoiseSigma(m.data, static_cast<std::ptrdiff_t>(m.step[0]), m.cols, m.rows);
}

cv::Mat WithNoise(const cv::Mat& gray, double sigma, int seed) {
  cv::Mat out = gray.clone();
  ellipsekit::eval::AddSensorNoise(sigma, static_cast<std::uint64_t>(seed), &out);
  return out;
}

TEST(NoiseSigma, IsZeroWithoutNoiseWhateverTheEdges) {
  cv::Mat plane(48, 64, CV_8UC1);
  for (int y = 0; y < plane.rows; ++y)
    for (int x = 0; x < plane.cols; ++x) plane.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(10 + x + 2 * y);
  EXPECT_EQ(Sigma(plane), 0.0) << "a plane";
  cv::Mat step(48, 64, CV_8UC1, cv::Scalar(40));
  step.colRange(32, 64).setTo(200);
  EXPECT_EQ(Sigma(step), 0.0) << "a step edge: two columns of 62";
  cv::Mat disc(120, 160, CV_8UC1, cv::Scalar(60));
  cv::circle(disc, {80, 60}, 40, cv::Scalar(220), cv::FILLED, cv::LINE_AA);
  EXPECT_EQ(Sigma(disc), 0.0) << "a sharp disc";
  EXPECT_EQ(Sigma(cv::Mat(2, 64, CV_8UC1, cv::Scalar(9))), 0.0) << "under 3 rows";
  EXPECT_EQ(Sigma(cv::Mat(64, 2, CV_8UC1, cv::Scalar(9))), 0.0) << "under 3 columns";
}

// White noise of standard deviation s on a flat grey, and on a frame with edges. Measured: 1.98,
// 3.95, 7.91, 11.86 for s = 2, 4, 8, 12 on both (the median moves in steps of 0.247); held within
// 0.25 + 0.04 s.
TEST(NoiseSigma, ReadsTheStandardDeviationOfWhiteNoise) {
  cv::Mat disc(240, 320, CV_8UC1, cv::Scalar(90));
  cv::circle(disc, {160, 120}, 80, cv::Scalar(170), cv::FILLED, cv::LINE_AA);
  for (const double s : {2.0, 4.0, 8.0, 12.0}) {
    const double flat = Sigma(WithNoise(cv::Mat(240, 320, CV_8UC1, cv::Scalar(128)), s, 3));
    const double edged = Sigma(WithNoise(disc, s, 4));
    std::printf("noise %.0f: flat reads %.2f, disc reads %.2f\n", s, flat, edged);
    EXPECT_NEAR(flat, s, 0.25 + 0.04 * s) << s;
    EXPECT_NEAR(edged, s, 0.25 + 0.04 * s) << s;
  }
}

// Clipped pixels (0 or 255) have lost their noise and are left out: a noisy frame whose left 60 %
// is black or saturated reads near the noise of the rest. Measured: 6.42 for both (the clipped
// side's unclipped half, its noise cut to one sign, still pulls it down; with the clipped pixels
// counted it read 5.44 and 5.19, under denoise_min_sigma's 6).
TEST(NoiseSigma, LeavesClippedPixelsOut) {
  for (const int clipped : {0, 255}) {
    cv::Mat frame(240, 320, CV_8UC1, cv::Scalar(128));
    frame.colRange(0, 192).setTo(clipped);
    ellipsekit::eval::AddSensorNoise(8, 5, &frame);  // saturated: the clipped side stays mostly clipped
    const double sigma = Sigma(frame);
    std::printf("left 60 %% at %d, noise 8: reads %.2f\n", clipped, sigma);
    EXPECT_GE(sigma, 6.0) << clipped;
    EXPECT_LE(sigma, 9.0) << clipped;
  }
}

// 20 generated scenes (seed 7) with noise of standard deviation 10 added: the edges of the frame as
// it is break into short, wobbly pieces. Measured (this test's printout): 55 tops; the defaults
// (two extra passes: the estimate reads ~10.4) find 44, without the smoothing 33.
TEST(Denoise, NoisyScenesAreSmoothedBeforeTheirEdges) {
  ellipsekit::Options off;
  off.denoise_min_sigma = 0;
  ellipsekit::Detector with(ellipsekit::Options{}), without(off);
  int truth = 0, found_with = 0, found_without = 0;
  for (int i = 0; i < 20; ++i) {
    const ellipsekit::scenes::Scene s = ellipsekit::scenes::RenderScene(ellipsekit::scenes::MixSeed(7, i));
    const cv::Mat noisy = WithNoise(s.gray, 10, 100 + i);
    const ellipsekit::ImageView view{noisy.data, noisy.cols, noisy.rows, static_cast<std::ptrdiff_t>(noisy.step[0])};
    ellipsekit::DetectionResult a, b;
    ASSERT_TRUE(with.detect(view, &a).ok());
    ASSERT_TRUE(without.detect(view, &b).ok());
    truth += static_cast<int>(s.truth.size());
    found_with += ellipsekit::eval::MatchEllipses(a.ellipses, s.truth).counts.correct;
    found_without += ellipsekit::eval::MatchEllipses(b.ellipses, s.truth).counts.correct;
  }
  std::printf("20 scenes + noise 10: %d tops, %d found with the smoothing, %d without\n", truth, found_with,
              found_without);
  EXPECT_GE(found_with, 0.7 * truth);
  EXPECT_GE(found_with, found_without + truth / 10) << "the smoothing no longer pays for itself: re-measure";
}

// The smoothing runs on the CPU before every backend's edge stage: scalar, SIMD and Vulkan (where
// a device is) find the same ellipses on a smoothed frame, bit for bit (DESIGN.md "Backends agree").
TEST(Denoise, BackendsAgreeOnSmoothedFrames) {
  int ellipses = 0, compared = 0;
  for (int scene = 0; scene < 4; ++scene) {
    const ellipsekit::scenes::Scene s = ellipsekit::scenes::RenderScene(ellipsekit::scenes::MixSeed(7, scene));
    const cv::Mat noisy = WithNoise(s.gray, scene % 2 ? 10 : 7, scene);  // two passes, one pass
    const ellipsekit::ImageView view{noisy.data, noisy.cols, noisy.rows, static_cast<std::ptrdiff_t>(noisy.step[0])};
    ellipsekit::Options o;
    o.backend = ellipsekit::Backend::kScalar;
    ellipsekit::DetectionResult want;
    ASSERT_TRUE(ellipsekit::Detector(o).detect(view, &want).ok());
    EXPECT_EQ(want.denoise_passes, scene % 2 ? 2 : 1) << "noise " << want.noise_sigma;
    ellipses += static_cast<int>(want.ellipses.size());
    for (const ellipsekit::Backend b : {ellipsekit::Backend::kSimd, ellipsekit::Backend::kVulkan}) {
      o.backend = b;
      ellipsekit::Detector det(o);
      if (!det.status().ok()) {
        std::printf("%s not available here: %s\n", ellipsekit::BackendName(b), det.status().message().c_str());
        continue;
      }
      const std::string where = std::string(ellipsekit::BackendName(b)) + ", scene " + std::to_string(scene);
      ellipsekit::DetectionResult got;
      ASSERT_TRUE(det.detect(view, &got).ok());
      EXPECT_EQ(got.noise_sigma, want.noise_sigma) << where;
      EXPECT_EQ(got.denoise_passes, want.denoise_passes) << where;
      EXPECT_EQ(got.num_edge_pixels, want.num_edge_pixels) << where;
      EXPECT_TRUE(ellipsekit::test::SameEllipses(got.ellipses, want.ellipses)) << where;
      ++compared;
    }
  }
  std::printf("4 noisy scenes, %d ellipses, the same on the scalar and %d other backend runs\n", ellipses, compared);
  EXPECT_GE(ellipses, 5);
}

TEST(Denoise, OptionIsChecked) {
  ellipsekit::Options o;
  ASSERT_TRUE(ellipsekit::SetOption("denoise_min_sigma=nan", &o).ok());
  EXPECT_FALSE(ellipsekit::ValidateOptions(o).ok());
  ASSERT_TRUE(ellipsekit::SetOption("denoise_min_sigma=-1", &o).ok());
  EXPECT_TRUE(ellipsekit::ValidateOptions(o).ok()) << "<= 0 means never";
}

}  // namespace
