// Local grouping (issue "Crowded scenes"): the arc end-point index against brute force, the
// clustering's centre grid against the plain scan it replaces, and on crowded frames: every ring
// of a 15x10 grid found, a frame whose triplet budget runs out still finds ellipses in all four
// quadrants of the image, and pairs per ellipse that do not grow with the ellipses in the frame.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "ellipsekit/detector.h"
#include "fit/arc_index.h"
#include "fit/clustering.h"
#include "tools/eval/metrics.h"
#include "tools/scenes/crowded_scenes.h"
#include "tools/scenes/rng.h"

namespace ellipsekit {
namespace {

using scenes::CrowdedLayout;
using scenes::CrowdedSceneOptions;

ImageView View(const cv::Mat& gray) {
  return {gray.data, gray.cols, gray.rows, static_cast<std::ptrdiff_t>(gray.step[0])};
}

std::vector<Arc> RandomArcs(std::uint64_t seed, int n, double extent) {
  scenes::Rng rng(seed);
  std::vector<Arc> arcs(static_cast<std::size_t>(n));
  for (Arc& a : arcs) {
    a.p0 = {rng.Uniform(0, extent), rng.Uniform(0, extent)};
    a.p1 = a.p0 + Eigen::Vector2d(rng.Uniform(-60, 60), rng.Uniform(-60, 60));
    a.quadrant = rng.Int(1, 4);
  }
  return arcs;
}

TEST(ArcEndIndex, FindsExactlyTheArcsWithAnEndWithinTheRadius) {
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const std::vector<Arc> arcs = RandomArcs(seed, 400, 700);
    ArcEndIndex index;
    index.Reserve(800, 800, arcs.size());
    index.Build(arcs);
    int found_total = 0;
    for (const Arc& probe : arcs) {
      for (double radius : {0.0, 5.0, 40.0, 150.0, HUGE_VAL}) {
        for (int q = 1; q <= 4; ++q) {
          std::vector<int> got, want;
          index.ForEachNear(arcs, probe, q, radius, [&](int j, double d) {
            EXPECT_EQ(d, ArcEndIndex::EndDistance(probe, arcs[j]));
            got.push_back(j);
          });
          for (int j = 0; j < static_cast<int>(arcs.size()); ++j) {
            if (arcs[j].quadrant == q && ArcEndIndex::EndDistance(probe, arcs[j]) <= radius) want.push_back(j);
          }
          std::sort(got.begin(), got.end());
          ASSERT_EQ(got, want) << "seed " << seed << " radius " << radius << " quadrant " << q;
          found_total += static_cast<int>(got.size());
        }
      }
    }
    EXPECT_GT(found_total, 0);
  }
}

TEST(ArcEndIndex, EmptyAndSinglePointFrames) {
  ArcEndIndex index;
  std::vector<Arc> arcs;
  index.Build(arcs);
  Arc probe;
  probe.quadrant = 1;
  int calls = 0;
  index.ForEachNear(arcs, probe, 1, 10, [&](int, double) { ++calls; });
  EXPECT_EQ(calls, 0);
  arcs.push_back(probe);  // both ends at the origin: a one-cell grid
  index.Build(arcs);
  index.ForEachNear(arcs, probe, 1, 0, [&](int, double) { ++calls; });
  EXPECT_EQ(calls, 1);
}

// The clustering loop as it was before the centre grid: each candidate is compared with every
// reference in order.
std::vector<Ellipse> ClusterByScan(std::vector<Candidate> c, const Options& options) {
  std::sort(c.begin(), c.end(), [](const Candidate& x, const Candidate& y) {
    return x.ellipse.score > y.ellipse.score;
  });
  std::vector<Ellipse> kept;
  for (const Candidate& k : c) {
    bool joined = false;
    for (const Ellipse& r : kept) {
      if (SameEllipse(k.ellipse, r, options)) {
        joined = true;
        break;
      }
    }
    if (!joined) kept.push_back(k.ellipse);
  }
  return kept;
}

TEST(ClusterScratch, SameClustersAsComparingWithEveryReference) {
  for (ClusterRule rule : {ClusterRule::kFeatureDistance, ClusterRule::kRelative}) {
    Options o;
    o.cluster_rule = rule;
    o.cluster_pick_best_fit = false;
    o.cluster_outer_margin = -1;  // no rims: references are then the kept ellipses themselves
    scenes::Rng rng(42);
    std::vector<Candidate> c(3000);
    for (std::size_t i = 0; i < c.size(); ++i) {
      Ellipse& e = c[i].ellipse;
      // Clumps of near-duplicates (up to 8 of one ellipse) over a wide frame, a few far outside it.
      scenes::Rng clump(i / 8);
      const double x = clump.Int(0, 40) * 50.0, y = clump.Int(0, 30) * 50.0, a = clump.Uniform(8, 60);
      e.cx = x + rng.Uniform(-4, 4) + (i % 97 == 0 ? 1e5 : 0);
      e.cy = y + rng.Uniform(-4, 4);
      e.a = a * rng.Uniform(0.9, 1.1);
      e.b = e.a * clump.Uniform(0.5, 0.95);
      e.theta = clump.Uniform(-1.5, 1.5) + rng.Uniform(-0.05, 0.05);
      e.score = rng.Uniform(0, 2);  // distinct scores: both orders are the same total order
    }
    const std::vector<Ellipse> want = ClusterByScan(c, o);
    ClusterScratch scratch;
    const int kept = ClusterCandidates(&c, o, nullptr, &scratch);
    ASSERT_EQ(kept, static_cast<int>(want.size()));
    for (int k = 0; k < kept; ++k) EXPECT_EQ(c[k].ellipse.cx, want[k].cx) << "reference " << k;
    EXPECT_GT(kept, 100);
    EXPECT_LT(kept, 3000);
  }
}

TEST(SameEllipse, ConcentricEllipsesOfVeryDifferentSizeAreTwo) {
  Options o;  // eq. 17, T_s = 25 px
  const Ellipse outer{100, 100, 16, 12, 0.3, 0};
  Ellipse inner = outer;
  inner.a *= 0.6;
  inner.b *= 0.6;  // a printed ring's two edges: D = 8 px < T_s, but 1.67x larger
  EXPECT_LT(FeatureDistance(outer, inner), o.cluster_distance);
  EXPECT_FALSE(SameEllipse(outer, inner, o));
  Ellipse lip = outer;
  lip.a *= 0.85;
  lip.b *= 0.85;  // a can's inner lip: one cluster, whose outer rim represents it
  EXPECT_TRUE(SameEllipse(outer, lip, o));
  Ellipse below = inner;
  below.cy += 6;  // not concentric: eq. 17 alone decides
  EXPECT_TRUE(SameEllipse(outer, below, o));
}

CrowdedSceneOptions Layout(int width, int height, CrowdedLayout layout, int objects, double max_tilt_deg) {
  CrowdedSceneOptions o;
  o.width = width;
  o.height = height;
  o.layout = layout;
  o.objects = objects;
  o.max_tilt_deg = max_tilt_deg;
  return o;
}

struct Found {
  int truth = 0, correct = 0, detected = 0;
  unsigned caps = 0;
  int pairs = 0, triplets = 0;
  std::vector<Ellipse> ellipses;
};

Found DetectScene(const scenes::Scene& s, const Options& options = {}) {
  Detector d(options);
  DetectionResult r;
  EXPECT_TRUE(d.detect(View(s.gray), &r).ok());
  const eval::MatchResult m = eval::MatchEllipses(r.ellipses, s.truth);
  Found f;
  f.truth = static_cast<int>(s.truth.size());
  f.correct = m.counts.correct;
  f.detected = static_cast<int>(r.ellipses.size());
  f.caps = r.caps_hit;
  f.pairs = r.num_pairs;
  f.triplets = r.num_triplets;
  f.ellipses = r.ellipses;
  return f;
}

// Rings whose edges the paper's thresholds can see: semi-minor axes >= 12 px (a quarter of a
// smaller ellipse is near T_n = 15 points) and inner radius <= 0.65 of the outer (above 0.69 the
// outer edge is taken for the rim of the inner one, tools/scenes/crowded_scenes.h). Measured:
// 300, 300 and 299 of 300 edges for seeds 1-3 (the one missed: an outer edge whose cluster a
// two-arc fit of its own inner edge took); the test allows two misses per frame.
TEST(CrowdedScenes, EveryRingOfA15x10GridIsFound) {
  CrowdedSceneOptions o = Layout(1920, 1080, CrowdedLayout::kRingGrid, 150, 30);
  o.min_semi_minor_px = 12;
  o.max_ring_ratio = 0.65;
  for (std::uint64_t seed : {1, 2, 3}) {
    const scenes::Scene s = scenes::RenderCrowdedScene(seed, o);
    ASSERT_EQ(s.truth.size(), 300u);  // both edges of 150 rings
    const Found f = DetectScene(s);
    EXPECT_EQ(f.caps, 0u) << "seed " << seed;
    EXPECT_GE(f.correct, 298) << "seed " << seed << ": " << f.detected << " detected";
    EXPECT_LE(f.detected - f.correct, 2) << "seed " << seed;
  }
}

// The triplet budget cut to a quarter of what a 300-dot frame examines: pass 1 gives every
// middle arc of the frame an equal share, visited spread over the frame (grouping.cc SpreadOverFrame),
// so each quadrant of the layout keeps its share of the detections. (A frame that exhausts the
// budget also skips the two-arc candidates, fit/grouping.h; the dots are large enough here for
// triplets.)
TEST(CrowdedScenes, ABudgetThatRunsOutStillFindsEllipsesInEveryQuadrant) {
  CrowdedSceneOptions o = Layout(1280, 720, CrowdedLayout::kDotGrid, 300, 20);
  o.min_semi_minor_px = 14;
  const scenes::Scene s = scenes::RenderCrowdedScene(11, o);
  ASSERT_EQ(s.truth.size(), 300u);
  const Found all = DetectScene(s);
  ASSERT_EQ(all.caps, 0u);
  ASSERT_GE(all.correct, 295);
  Options tight;
  tight.max_triplets = std::max(1, all.triplets / 4);
  const Found f = DetectScene(s, tight);
  ASSERT_TRUE(f.caps & kCapTriplets);
  // The layout's centre splits its dots into four quadrants; each must keep detections.
  double cx = 0, cy = 0;
  for (const Ellipse& t : s.truth) { cx += t.cx; cy += t.cy; }
  cx /= s.truth.size();
  cy /= s.truth.size();
  int per_quadrant[4] = {0, 0, 0, 0};
  for (const Ellipse& e : f.ellipses) ++per_quadrant[(e.cx >= cx) + 2 * (e.cy >= cy)];
  // Measured: 75 found with a budget of 75, 19 / 20 / 18 / 18 per quadrant; longest first alone
  // gave 22 / 28 / 9 / 16 (the far side of the tilted grid starves).
  EXPECT_GE(f.correct, tight.max_triplets * 9 / 10);
  for (int q = 0; q < 4; ++q) EXPECT_GE(per_quadrant[q], f.correct / 5) << "quadrant " << q;
  std::printf("[budget] %d triplets for all, cap %d: %d of 300 found, per quadrant %d %d %d %d\n", all.triplets,
              tight.max_triplets, f.correct, per_quadrant[0], per_quadrant[1], per_quadrant[2], per_quadrant[3]);
}

TEST(CrowdedScenes, PairsPerEllipseDoNotGrowWithTheEllipses) {
  CrowdedSceneOptions o = Layout(1280, 720, CrowdedLayout::kDotGrid, 25, 30);
  const Found few = DetectScene(scenes::RenderCrowdedScene(5, o));
  o.objects = 300;
  const Found many = DetectScene(scenes::RenderCrowdedScene(5, o));
  ASSERT_GT(few.correct, 20);
  ASSERT_GT(many.correct, 250);
  const double few_rate = static_cast<double>(few.pairs) / few.truth;
  const double many_rate = static_cast<double>(many.pairs) / many.truth;
  // The half-plane test alone gave pairs growing with the square of the dots (x12 here).
  EXPECT_LT(many_rate, 2 * few_rate) << few.pairs << " pairs for " << few.truth << ", " << many.pairs << " for "
                                     << many.truth;
}

}  // namespace
}  // namespace ellipsekit
