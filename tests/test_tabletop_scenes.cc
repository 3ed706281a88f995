// The hard tabletop set (tools/scenes/tabletop_scenes.h): option checks, determinism, the truth is
// the projected rim, meta lines match truth lines, and the visible fraction (1 for a top inside the
// frame and unhidden, the in-frame share for a top cut by the frame's edge, < 1 behind a box).
#include <algorithm>
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "tests/ellipse_test_util.h"
#include "tools/eval/breakdown.h"
#include "tools/eval/dataset.h"
#include "tools/eval/ellipse_io.h"
#include "tools/scenes/tabletop_scenes.h"

namespace ellipsekit::scenes {
namespace {

constexpr double kPi = 3.14159265358979323846;

TabletopSceneOptions Small() {
  TabletopSceneOptions o;
  o.width = 320;
  o.height = 240;
  return o;
}

// Image of rim point k of n (the 360 samples of the visible fraction when n = 360).
bool ProjectRim(const TabletopScene& s, const TabletopTop& top, int k, int n, double* u, double* v) {
  const double phi = 2 * kPi * k / n;
  const cv::Vec3d P = top.rim_centre + cv::Vec3d(std::cos(phi), std::sin(phi), 0) * top.rim_radius_m;
  const cv::Vec3d x = s.K * (s.R * P + s.t);
  if (x[2] <= 0) return false;
  *u = x[0] / x[2];
  *v = x[1] / x[2];
  return true;
}

TEST(TabletopScenes, RefusesBadOptionsByName) {
  TabletopSceneOptions o;
  o.width = 10;
  EXPECT_NE(ValidateTabletopSceneOptions(o).message().find("size"), std::string::npos);
  o = {};
  o.min_containers = 5;
  o.max_containers = 4;
  EXPECT_NE(ValidateTabletopSceneOptions(o).message().find("containers"), std::string::npos);
  o = {};
  o.max_distance_m = NAN;
  EXPECT_NE(ValidateTabletopSceneOptions(o).message().find("distance"), std::string::npos);
  o = {};
  o.min_visible_fraction = 0;
  EXPECT_NE(ValidateTabletopSceneOptions(o).message().find("min_visible_fraction"), std::string::npos);
  EXPECT_TRUE(RenderTabletopScene(1, o).gray.empty());
  EXPECT_FALSE(WriteTabletopDataset(testing::TempDir() + "/tabletop_bad", 1, 1, o).ok());
}

TEST(TabletopScenes, KindNamesRoundTrip) {
  for (int k = 0; k < kTabletopKinds; ++k) {
    TabletopKind parsed = TabletopKind::kCan;
    ASSERT_TRUE(ParseTabletopKind(TabletopKindName(static_cast<TabletopKind>(k)), &parsed));
    EXPECT_EQ(parsed, static_cast<TabletopKind>(k));
  }
  TabletopKind unused;
  EXPECT_FALSE(ParseTabletopKind("tray", &unused));
}

TEST(TabletopScenes, DeterministicPerSeed) {
  const TabletopScene a = RenderTabletopScene(5, Small()), b = RenderTabletopScene(5, Small());
  const TabletopScene c = RenderTabletopScene(6, Small());
  ASSERT_FALSE(a.gray.empty());
  EXPECT_EQ(a.gray.cols, 320);
  EXPECT_EQ(cv::norm(a.gray, b.gray, cv::NORM_INF), 0);
  ASSERT_EQ(a.truth.size(), b.truth.size());
  for (std::size_t i = 0; i < a.truth.size(); ++i) {
    EXPECT_EQ(FormatTruthLine(a.truth[i]), FormatTruthLine(b.truth[i]));
    EXPECT_EQ(FormatTabletopMetaLine(a.tops[i]), FormatTabletopMetaLine(b.tops[i]));
  }
  EXPECT_GT(cv::norm(a.gray, c.gray, cv::NORM_INF), 0);
}

// Every rim point, projected by the scene's camera, lies on its truth ellipse; every top keeps the
// promised share of its rim and a semi-minor axis >= 5 px; containers per frame within 2..8.
TEST(TabletopScenes, TruthIsTheProjectedRim) {
  int tops = 0, kinds_seen = 0;
  bool seen[kTabletopKinds] = {};
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    const TabletopScene s = RenderTabletopScene(MixSeed(3, seed), Small());
    ASSERT_EQ(s.truth.size(), s.tops.size());
    EXPECT_GE(s.truth.size(), 1u);
    EXPECT_LE(s.truth.size(), 8u);
    for (std::size_t i = 0; i < s.truth.size(); ++i) {
      const Ellipse& e = s.truth[i];
      const ellipsekit::test::TrueEllipse truth{e.cx, e.cy, e.a, e.b, e.theta};
      const TabletopTop& top = s.tops[i];
      EXPECT_GE(e.b, 5.0);
      EXPECT_GE(top.visible_fraction, Small().min_visible_fraction);
      EXPECT_LE(top.visible_fraction, top.in_frame_fraction);
      for (int k = 0; k < 72; ++k) {
        double u = 0, v = 0;
        ASSERT_TRUE(ProjectRim(s, top, k, 72, &u, &v));
        // (x/a)^2 + (y/b)^2 - 1 = 0 on the ellipse; 1e-3 is < 0.01 px at these sizes.
        EXPECT_NEAR(truth.Algebraic({u, v}), 0.0, 1e-3) << "seed " << seed << " top " << i;
      }
      EXPECT_NE(top.kind, TabletopKind::kBottle) << "bottles only with TabletopSceneOptions::bottles";
      seen[static_cast<int>(top.kind)] = true;
      ++tops;
    }
  }
  for (bool k : seen) kinds_seen += k;
  EXPECT_GE(tops, 12);
  EXPECT_GE(kinds_seen, 4);
}

// With bottles: a bottle's truth is its cap's top rim, 12-17 mm in radius and 16-26 cm above the
// table, where the image shows it: along a fully visible cap rim the image 2 px inside differs
// from 2 px outside (the contrast fix), as it does for the other kinds.
TEST(TabletopScenes, BottleTruthIsTheCapRimHighAboveTheTable) {
  TabletopSceneOptions o = Small();
  o.bottles = true;
  int bottles = 0, visible = 0;
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    const TabletopScene s = RenderTabletopScene(MixSeed(5, seed), o);
    for (std::size_t i = 0; i < s.tops.size(); ++i) {
      const TabletopTop& top = s.tops[i];
      if (top.kind != TabletopKind::kBottle) continue;
      ++bottles;
      EXPECT_GE(top.rim_radius_m, 0.012);
      EXPECT_LE(top.rim_radius_m, 0.017);
      EXPECT_GE(top.rim_centre[2], 0.16);
      EXPECT_LE(top.rim_centre[2], 0.26);
      const Ellipse& e = s.truth[i];
      const ellipsekit::test::TrueEllipse truth{e.cx, e.cy, e.a, e.b, e.theta};
      std::vector<double> steps;
      for (int k = 0; k < 36; ++k) {
        double u = 0, v = 0;
        ASSERT_TRUE(ProjectRim(s, top, k, 36, &u, &v));
        EXPECT_NEAR(truth.Algebraic({u, v}), 0.0, 1e-3) << "seed " << seed << " top " << i;
        const double dx = u - e.cx, dy = v - e.cy, len = std::hypot(dx, dy);
        const int xi = static_cast<int>(std::lround(u - 2 * dx / len)), yi = static_cast<int>(std::lround(v - 2 * dy / len));
        const int xo = static_cast<int>(std::lround(u + 2 * dx / len)), yo = static_cast<int>(std::lround(v + 2 * dy / len));
        if (std::min({xi, yi, xo, yo}) < 0 || std::max(xi, xo) >= s.gray.cols || std::max(yi, yo) >= s.gray.rows) continue;
        steps.push_back(std::abs(s.gray.at<std::uint8_t>(yi, xi) - s.gray.at<std::uint8_t>(yo, xo)));
      }
      if (top.visible_fraction < 1 || steps.size() < 36) continue;
      ++visible;
      std::sort(steps.begin(), steps.end());
      EXPECT_GE(steps[steps.size() / 2], 8) << "seed " << seed << " top " << i;
    }
  }
  EXPECT_GE(bottles, 4);
  EXPECT_GE(visible, 2);
}

// One container, no boxes: nothing can hide its top but the frame's edge, so its visible fraction
// is exactly the share of the 360 rim samples projecting inside the frame: 1 when the whole
// ellipse is inside, < 1 when the frame cuts it.
TEST(TabletopScenes, VisibleFractionIsOneInsideTheFrameAndTheInFrameShareWhenCut) {
  TabletopSceneOptions o = Small();
  o.width = 160;
  o.height = 120;
  o.min_containers = o.max_containers = 1;
  o.max_boxes = 0;
  o.edge_cut_share = 0.6;
  int inside = 0, cut = 0;
  for (std::uint64_t seed = 1; seed <= 40 && (inside < 2 || cut < 2); ++seed) {
    const TabletopScene s = RenderTabletopScene(seed, o);
    ASSERT_LE(s.tops.size(), 1u);
    if (s.tops.empty()) continue;
    const TabletopTop& top = s.tops[0];
    int in = 0;
    for (int k = 0; k < 360; ++k) {
      double u = 0, v = 0;
      if (ProjectRim(s, top, k, 360, &u, &v) && u >= -0.5 && u < o.width - 0.5 && v >= -0.5 && v < o.height - 0.5)
        ++in;
    }
    EXPECT_NEAR(top.visible_fraction, in / 360.0, 1.5 / 360) << "seed " << seed;
    const Ellipse& e = s.truth[0];
    const double ex = std::hypot(e.a * std::cos(e.theta), e.b * std::sin(e.theta));
    const double ey = std::hypot(e.a * std::sin(e.theta), e.b * std::cos(e.theta));
    if (e.cx - ex >= 0 && e.cx + ex <= o.width - 1 && e.cy - ey >= 0 && e.cy + ey <= o.height - 1) {
      EXPECT_EQ(top.visible_fraction, 1.0) << "seed " << seed;
      ++inside;
    } else if (in < 360) {
      EXPECT_LT(top.visible_fraction, 1.0) << "seed " << seed;
      ++cut;
    }
  }
  EXPECT_GE(inside, 2);
  EXPECT_GE(cut, 2);
}

// With boxes and several containers, some top inside the frame is partly hidden (visible < 1).
TEST(TabletopScenes, BoxesAndContainersHideSomeTops) {
  int hidden = 0;
  for (std::uint64_t seed = 1; seed <= 12 && hidden == 0; ++seed) {
    const TabletopScene s = RenderTabletopScene(seed, Small());
    for (const TabletopTop& top : s.tops)
      if (top.in_frame_fraction == 1.0 && top.visible_fraction < 1.0) ++hidden;
  }
  EXPECT_GT(hidden, 0);
}

// The dataset: images/, gt/ and meta/ with one meta line per gt line, equal to the rendered scene.
TEST(TabletopScenes, DatasetMetaLinesMatchTruthLines) {
  const std::string dir = testing::TempDir() + "/tabletop_dataset";
  std::filesystem::remove_all(dir);
  ASSERT_TRUE(WriteTabletopDataset(dir, 3, 11, Small()).ok());
  eval::Dataset ds;
  ASSERT_TRUE(eval::LoadDataset(dir, &ds).ok());
  ASSERT_EQ(ds.images.size(), 3u);
  for (std::size_t i = 0; i < ds.images.size(); ++i) {
    std::vector<Ellipse> truth;
    std::vector<eval::TruthMeta> meta;
    ASSERT_TRUE(eval::ReadEllipses(ds.images[i].truth_path, &truth).ok());
    ASSERT_TRUE(eval::ReadTruthMeta(eval::TruthMetaPath(dir, ds.images[i].stem), &meta).ok());
    const TabletopScene s = RenderTabletopScene(MixSeed(11, i), Small());
    ASSERT_EQ(truth.size(), s.truth.size());
    ASSERT_EQ(meta.size(), truth.size());
    for (std::size_t k = 0; k < meta.size(); ++k) {
      EXPECT_EQ(meta[k].kind, TabletopKindName(s.tops[k].kind));
      EXPECT_NEAR(meta[k].visible_fraction, s.tops[k].visible_fraction, 1e-4);
      EXPECT_NEAR(truth[k].cx, s.truth[k].cx, 1e-4);
      EXPECT_NEAR(truth[k].b, s.truth[k].b, 1e-4);
    }
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ellipsekit::scenes
