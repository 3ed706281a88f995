// The crowd pass (Options::crowd_min_curve_points, runtime/detector_crowd.cc): a frame of dots too
// small for T_n is found with it and not without; frames that are no crowd give exactly what the
// first pass gives; every CPU backend (and Vulkan where a device is present) agrees bit for bit.
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "ellipsekit/detector.h"
#include "tools/eval/metrics.h"
#include "tools/scenes/crowded_scenes.h"
#include "tools/scenes/rng.h"
#include "tools/scenes/scene_generator.h"
#include "tests/ellipse_test_util.h"

namespace ellipsekit {
namespace {

ImageView View(const cv::Mat& gray) {
  return {gray.data, gray.cols, gray.rows, static_cast<std::ptrdiff_t>(gray.step[0])};
}

std::vector<Ellipse> Detect(const cv::Mat& gray, Options o) {
  Detector d(o);
  EXPECT_TRUE(d.status().ok()) << d.status().message();
  DetectionResult r;
  EXPECT_TRUE(d.detect(View(gray), &r).ok());
  EXPECT_EQ(r.caps_hit, 0u);
  return r.ellipses;
}

Options CrowdPassOff() {
  Options o;
  o.crowd_min_curve_points = o.min_curve_points;
  return o;
}

// Scene 19 of `ellipsekit scenes --crowded --layout dots --size 1024x768 --objects 300 --seed 9`:
// 300 dots whose outlines trace as curves of 12-14 points. Measured: 0 found by the first pass,
// 274 correct with the crowd pass, none false.
scenes::Scene SmallDots() {
  scenes::CrowdedSceneOptions o;
  o.width = 1024;
  o.height = 768;
  o.layout = scenes::CrowdedLayout::kDotGrid;
  o.objects = 300;
  return scenes::RenderCrowdedScene(scenes::MixSeed(9, 19), o);
}

TEST(CrowdPass, FindsDotsTooSmallForTheFirstPass) {
  const scenes::Scene s = SmallDots();
  ASSERT_EQ(s.truth.size(), 300u);
  const eval::MatchResult off = eval::MatchEllipses(Detect(s.gray, CrowdPassOff()), s.truth);
  const std::vector<Ellipse> found = Detect(s.gray, Options{});
  const eval::MatchResult on = eval::MatchEllipses(found, s.truth);
  std::printf("[crowd] first pass alone %d correct; with the crowd pass %d correct of %zu detected\n",
              off.counts.correct, on.counts.correct, found.size());
  EXPECT_LT(off.counts.correct, 30);
  EXPECT_GE(on.counts.correct, 260);
  EXPECT_LE(static_cast<int>(found.size()) - on.counts.correct, 3);
}

// Tabletop scenes (2-8 tops, texture, no crowd of small ellipses): the pass does not run, or adds
// nothing; the ellipses are exactly the first pass's.
TEST(CrowdPass, LeavesFramesWithoutACrowdAsTheyWere) {
  for (std::uint64_t i = 0; i < 20; ++i) {
    const scenes::Scene s = scenes::RenderScene(scenes::MixSeed(7, i));
    EXPECT_TRUE(test::SameEllipses(Detect(s.gray, Options{}), Detect(s.gray, CrowdPassOff()))) << "scene " << i;
  }
}

TEST(CrowdPass, BackendsAgreeBitForBit) {
  const scenes::Scene s = SmallDots();
  Options o;
  o.backend = Backend::kScalar;
  const std::vector<Ellipse> reference = Detect(s.gray, o);
  ASSERT_GT(reference.size(), 200u);
  for (Backend b : {Backend::kSimd, Backend::kVulkan}) {
    o.backend = b;
    Detector d(o);
    if (!d.status().ok()) {
      EXPECT_EQ(b, Backend::kVulkan) << d.status().message();  // only a missing device may refuse
      continue;
    }
    DetectionResult r;
    ASSERT_TRUE(d.detect(View(s.gray), &r).ok());
    EXPECT_TRUE(test::SameEllipses(r.ellipses, reference)) << BackendName(b);
  }
}

}  // namespace
}  // namespace ellipsekit
