// The crowded-scene generator (tools/scenes/crowded_scenes.h): option checks, determinism, the
// truth inside the frame and above the size floor, and the truth lying on the rendered edges.
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "tools/scenes/crowded_scenes.h"

namespace ellipsekit::scenes {
namespace {

TEST(CrowdedScenes, RefusesBadOptionsByName) {
  CrowdedSceneOptions o;
  o.width = 10;
  o.height = 10;
  EXPECT_NE(ValidateCrowdedSceneOptions(o).message().find("size"), std::string::npos);
  o = {};
  o.objects = -1;
  EXPECT_NE(ValidateCrowdedSceneOptions(o).message().find("objects"), std::string::npos);
  o = {};
  o.max_tilt_deg = NAN;
  EXPECT_NE(ValidateCrowdedSceneOptions(o).message().find("max_tilt_deg"), std::string::npos);
  o = {};
  o.min_semi_minor_px = -1;
  EXPECT_NE(ValidateCrowdedSceneOptions(o).message().find("min_semi_minor_px"), std::string::npos);
  o = {};
  o.layout = static_cast<CrowdedLayout>(99);
  EXPECT_NE(ValidateCrowdedSceneOptions(o).message().find("layout"), std::string::npos);
  EXPECT_TRUE(RenderCrowdedScene(1, o).gray.empty());
  EXPECT_FALSE(WriteCrowdedDataset(testing::TempDir() + "/crowded_bad", 1, 1, o).ok());
}

TEST(CrowdedScenes, LayoutNamesRoundTrip) {
  for (CrowdedLayout l : {CrowdedLayout::kAny, CrowdedLayout::kDotGrid, CrowdedLayout::kRingGrid,
                          CrowdedLayout::kCanCrate, CrowdedLayout::kCapTray, CrowdedLayout::kCupTray}) {
    CrowdedLayout parsed = CrowdedLayout::kAny;
    ASSERT_TRUE(ParseCrowdedLayout(CrowdedLayoutName(l), &parsed));
    EXPECT_EQ(parsed, l);
  }
  CrowdedLayout unused;
  EXPECT_FALSE(ParseCrowdedLayout("plates", &unused));
}

TEST(CrowdedScenes, DeterministicPerSeed) {
  CrowdedSceneOptions o;
  o.width = 320;
  o.height = 240;
  o.objects = 30;
  const Scene a = RenderCrowdedScene(9, o), b = RenderCrowdedScene(9, o), c = RenderCrowdedScene(10, o);
  ASSERT_EQ(a.truth.size(), b.truth.size());
  EXPECT_EQ(cv::norm(a.gray, b.gray, cv::NORM_INF), 0);
  EXPECT_GT(cv::norm(a.gray, c.gray, cv::NORM_INF), 0);
}

// CrowdedSceneOptions::clutter draws its bars, cables and marks after the layout and the camera,
// so a seed's cluttered truth is its plain truth less the circles hidden by more than half; over
// six seeds some are hidden, most are kept, and the frames differ.
TEST(CrowdedScenes, ClutterHidesPartsOfTheLayoutAndTheTruthKeepsWhatShows) {
  CrowdedSceneOptions plain;
  plain.width = 640;
  plain.height = 480;
  plain.objects = 60;
  CrowdedSceneOptions cluttered = plain;
  cluttered.clutter = true;
  std::size_t kept = 0, all = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    const Scene p = RenderCrowdedScene(seed, plain), c = RenderCrowdedScene(seed, cluttered);
    ASSERT_FALSE(c.gray.empty());
    EXPECT_GT(cv::norm(p.gray, c.gray, cv::NORM_INF), 0) << "seed " << seed;
    EXPECT_EQ(cv::norm(c.gray, RenderCrowdedScene(seed, cluttered).gray, cv::NORM_INF), 0) << "seed " << seed;
    std::size_t j = 0;  // the kept ones, in the plain truth's order
    for (const ellipsekit::Ellipse& e : p.truth) {
      if (j < c.truth.size() && c.truth[j].cx == e.cx && c.truth[j].cy == e.cy && c.truth[j].a == e.a) ++j;
    }
    EXPECT_EQ(j, c.truth.size()) << "seed " << seed << ": the cluttered truth is not a subset of the plain one";
    kept += c.truth.size();
    all += p.truth.size();
  }
  EXPECT_LT(kept, all) << "no circle was hidden in six seeds";
  EXPECT_GT(kept, all / 2) << "most circles should stay visible";
}

// Every layout at every drawn size: the number of truth ellipses, all inside the frame, none
// below the size floor; and the truth outline lies on the image's edges: the gray level changes
// across it (1.5 px inside vs 2.5 px outside) at most points of most ellipses.
TEST(CrowdedScenes, TruthInsideTheFrameAboveTheFloorAndOnTheEdges) {
  for (CrowdedLayout l : {CrowdedLayout::kDotGrid, CrowdedLayout::kRingGrid, CrowdedLayout::kCanCrate,
                          CrowdedLayout::kCapTray, CrowdedLayout::kCupTray}) {
    CrowdedSceneOptions o;
    o.layout = l;
    o.objects = 48;
    o.width = 960;
    o.height = 540;
    const Scene s = RenderCrowdedScene(3, o);
    ASSERT_FALSE(s.gray.empty());
    ASSERT_EQ(s.truth.size(), l == CrowdedLayout::kRingGrid ? 96u : 48u) << CrowdedLayoutName(l);
    cv::Mat smooth;
    cv::GaussianBlur(s.gray, smooth, cv::Size(3, 3), 0);
    int outlines_with_contrast = 0;
    for (const Ellipse& e : s.truth) {
      EXPECT_GE(e.b, o.min_semi_minor_px) << CrowdedLayoutName(l);
      const double c = std::cos(e.theta), sn = std::sin(e.theta);
      const double hx = std::sqrt(e.a * e.a * c * c + e.b * e.b * sn * sn);
      const double hy = std::sqrt(e.a * e.a * sn * sn + e.b * e.b * c * c);
      EXPECT_GE(e.cx - hx, 0);
      EXPECT_GE(e.cy - hy, 0);
      EXPECT_LE(e.cx + hx, o.width - 1);
      EXPECT_LE(e.cy + hy, o.height - 1);
      int contrast = 0;
      for (int k = 0; k < 32; ++k) {
        const double t = 2 * M_PI * k / 32;
        const double ux = std::cos(t), uy = std::sin(t);
        auto at = [&](double scale) {
          const double x = e.cx + scale * (e.a * ux * c - e.b * uy * sn);
          const double y = e.cy + scale * (e.a * ux * sn + e.b * uy * c);
          return static_cast<int>(smooth.at<std::uint8_t>(static_cast<int>(std::lround(y)), static_cast<int>(std::lround(x))));
        };
        // 1.5 px in: a cup's lip is a band of a tenth of its radius.
        const double in = 1 - 1.5 / e.b, out = 1 + 2.5 / e.b;
        contrast += std::abs(at(in) - at(out)) >= 12;
      }
      outlines_with_contrast += contrast >= 24;
    }
    EXPECT_GE(outlines_with_contrast, static_cast<int>(s.truth.size()) * 9 / 10) << CrowdedLayoutName(l);
  }
}

TEST(CrowdedScenes, DatasetFilesAsTheSceneDatasets) {
  const std::string dir = testing::TempDir() + "/crowded_ds";
  std::filesystem::remove_all(dir);
  CrowdedSceneOptions o;
  o.width = 320;
  o.height = 240;
  o.objects = 20;
  ASSERT_TRUE(WriteCrowdedDataset(dir, 2, 4, o).ok());
  for (const char* stem : {"scene_0000", "scene_0001"}) {
    EXPECT_TRUE(std::filesystem::exists(dir + "/images/" + stem + ".png"));
    EXPECT_TRUE(std::filesystem::exists(dir + "/gt/" + stem + ".txt"));
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ellipsekit::scenes
