// The image pyramid (kernels/pyramid_down.h, Options::pyramid_level / coarse_levels): the
// reduction against a brute-force 2x2 mean, the coordinates it reports, and what it buys on a
// photograph seen at 3x and 5.5x its resolution (cubic upscaling: the soft edges of a
// higher-resolution camera), where the detector at the frame's own level finds few of its ellipses.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "ellipsekit/detector.h"
#include "kernels/pyramid_down.h"
#include "tools/eval/ellipse_io.h"
#include "tools/eval/metrics.h"
#include "tools/scenes/scene_generator.h"

namespace {

using ellipsekit::Ellipse;

ellipsekit::ImageView View(const cv::Mat& m) {
  return {m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step[0])};
}

TEST(Pyramid, PyramidDownIsTheRoundedMeanOfEach2x2Block) {
  cv::RNG rng(5);
  for (const cv::Size size : {cv::Size(2, 2), cv::Size(3, 5), cv::Size(64, 48), cv::Size(129, 65)}) {
    cv::Mat src(size, CV_8UC1);
    rng.fill(src, cv::RNG::UNIFORM, 0, 256);
    const int w = size.width / 2, h = size.height / 2;
    std::vector<std::uint8_t> dst(static_cast<std::size_t>(w) * h + 1, 0xAB);  // + a guard byte
    ellipsekit::scalar::PyramidDown(src.data, static_cast<std::ptrdiff_t>(src.step[0]), size.width, size.height,
                                    dst.data(), w);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const int sum = src.at<std::uint8_t>(2 * y, 2 * x) + src.at<std::uint8_t>(2 * y, 2 * x + 1) +
                        src.at<std::uint8_t>(2 * y + 1, 2 * x) + src.at<std::uint8_t>(2 * y + 1, 2 * x + 1);
        ASSERT_EQ(dst[static_cast<std::size_t>(y) * w + x], (sum + 2) / 4) << size << " at " << x << "," << y;
      }
    }
    EXPECT_EQ(dst.back(), 0xAB) << "wrote past the reduced frame";
  }
  EXPECT_DOUBLE_EQ(ellipsekit::PyramidUp(0, 1), 0.5);   // dst pixel 0 covers src pixels 0 and 1
  EXPECT_DOUBLE_EQ(ellipsekit::PyramidUp(3, 2), 13.5);  // covers 12..15
}

// A scene detected at level 1 of its 2x-upscaled copy gives the ellipses of the scene itself,
// in the copy's coordinates: (c + 0.5) 2 - 0.5, axes twice.
TEST(Pyramid, CoordinatesOfALevelAreTheFrames) {
  const cv::Mat frame = ellipsekit::scenes::RenderScene(ellipsekit::scenes::MixSeed(7, 4)).gray;
  cv::Mat twice(frame.rows * 2, frame.cols * 2, CV_8UC1);
  cv::resize(frame, twice, twice.size(), 0, 0, cv::INTER_NEAREST);  // each pixel a 2x2 block
  ellipsekit::Options o;
  o.pyramid_level = 0;
  o.coarse_levels = 0;
  o.refit_to_image = false;  // the mapping itself (the refit is test_image_refit's)
  ellipsekit::Detector at_frame(o);
  o.pyramid_level = 1;
  ellipsekit::Detector at_level1(o);
  ellipsekit::DetectionResult want, got;
  ASSERT_TRUE(at_frame.detect(View(frame), &want).ok());
  ASSERT_TRUE(at_level1.detect(View(twice), &got).ok());
  ASSERT_GT(want.ellipses.size(), 0u);
  ASSERT_EQ(got.ellipses.size(), want.ellipses.size());
  for (std::size_t i = 0; i < want.ellipses.size(); ++i) {
    const Ellipse& w = want.ellipses[i];
    const Ellipse& g = got.ellipses[i];
    EXPECT_DOUBLE_EQ(g.cx, (w.cx + 0.5) * 2 - 0.5);
    EXPECT_DOUBLE_EQ(g.cy, (w.cy + 0.5) * 2 - 0.5);
    EXPECT_DOUBLE_EQ(g.a, 2 * w.a);
    EXPECT_DOUBLE_EQ(g.b, 2 * w.b);
    EXPECT_DOUBLE_EQ(g.theta, w.theta);
  }
}

// prasad_subset 027_0003 (720x435, 28 calculator keys) upscaled 3x (2160x1305) and 5.5x
// (3960x2393, 9.5 Mpx) with cubic interpolation, truth mapped alike. Measured (the defaults:
// coarse_levels 2, refit_to_image; at 5.5x pyramid_level auto picks level 2): 25 and 26 keys; with the frame's
// own level only (pyramid_level 0, coarse_levels 0): 11 and 0.
TEST(Pyramid, CalculatorKeysAtThreeAndFiveAndAHalfTimesTheResolution) {
  const std::string dir = std::string(ELLIPSEKIT_SOURCE_DIR) + "/../shared/datasets/prasad_subset/";
  const cv::Mat gray = cv::imread(dir + "images/027_0003.jpg", cv::IMREAD_GRAYSCALE);
  if (gray.empty()) GTEST_SKIP() << "no " << dir;
  std::vector<Ellipse> truth;
  ASSERT_TRUE(ellipsekit::eval::ReadEllipses(dir + "gt/027_0003.txt", &truth).ok());
  struct Case { double scale; int at_least, own_level_at_most; };
  for (const Case c : {Case{3, 22, 13}, Case{5.5, 23, 3}}) {
    cv::Mat big;
    cv::resize(gray, big, cv::Size(), c.scale, c.scale, cv::INTER_CUBIC);
    const double sx = static_cast<double>(big.cols) / gray.cols, sy = static_cast<double>(big.rows) / gray.rows;
    std::vector<Ellipse> scaled = truth;
    for (Ellipse& e : scaled) {
      e.cx = (e.cx + 0.5) * sx - 0.5;
      e.cy = (e.cy + 0.5) * sy - 0.5;
      e.a *= c.scale;
      e.b *= c.scale;
    }
    ellipsekit::Options own;
    own.pyramid_level = 0;
    own.coarse_levels = 0;
    for (const bool defaults : {true, false}) {
      ellipsekit::Detector det(defaults ? ellipsekit::Options() : own);
      ellipsekit::DetectionResult r;
      ASSERT_TRUE(det.detect(View(big), &r).ok());
      const int correct = ellipsekit::eval::MatchEllipses(r.ellipses, scaled).counts.correct;
      std::printf("027_0003 at %.1fx, %s: %d of 28 keys (%zu detections)\n", c.scale,
                  defaults ? "defaults" : "own level only", correct, r.ellipses.size());
      if (defaults) {
        EXPECT_GE(correct, c.at_least) << c.scale << "x";
      } else {
        EXPECT_LE(correct, c.own_level_at_most) << c.scale << "x: the frame's own level got better; re-measure";
      }
    }
  }
}

TEST(Pyramid, OptionsAreChecked) {
  for (const char* bad : {"pyramid_level=-2", "pyramid_level=5", "coarse_levels=5", "coarse_levels=-1",
                          "pyramid_max_pixels=0", "coarse_min_pixels=-1"}) {
    ellipsekit::Options o;
    ASSERT_TRUE(ellipsekit::SetOption(bad, &o).ok()) << bad;
    EXPECT_FALSE(ellipsekit::ValidateOptions(o).ok()) << bad;
  }
}

}  // namespace
