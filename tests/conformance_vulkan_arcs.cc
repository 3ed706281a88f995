// Conformance: the Vulkan arc stage (runtime/vulkan_arc_stage.h) against the scalar kernels, bit for
// bit: polylines, splits and arc statistics, on synthetic curves (8-connected random walks with
// fixed seeds, 1- and 2-point curves, straight lines, zig-zags, curves longer than 4096 points,
// coordinates near 16383) and on the curves of every shared dataset image, under several parameter
// sets; then whole Detector runs (Backend::kVulkan against kScalar) on the dataset images.
// No Vulkan device (or none with shaderInt64) -> the tests skip with the reason, except under
// CI=true (CI has lavapipe), where that is a failure. ELLIPSEKIT_VK_TIMING=1 also prints timings.
#include <gtest/gtest.h>

#if defined(ELLIPSEKIT_HAVE_VULKAN)

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "ellipsekit/detector.h"
#include "fit/arc_selection.h"
#include "kernels/arc_split.h"
#include "kernels/arc_stats.h"
#include "kernels/polyline.h"
#include "runtime/vulkan_arc_stage.h"
#include "tests/stage_test_util.h"

namespace ellipsekit {
namespace {

using stage_test::ViewOf;

#define REQUIRE_VULKAN(stage) REQUIRE_VULKAN_STAGE(VulkanArcStage, stage, "Vulkan arc stage")

struct ArcOutputs {
  Polylines polylines;
  Splits splits;
  std::vector<ArcStats> stats;
};

// Parameters as the kernels take them.
struct ArcParams {
  double tolerance_px, split_angle_deg;
  int min_points;
};
constexpr ArcParams kParamSets[] = {{1.0, 35.0, 15}, {0.5, 10.0, 1}, {2.0, 60.0, 3}, {4.0, 60.0, 2}, {0.25, 0.5, 4}};

// A record no kernel produces: both sides must append after it and leave it alone.
ArcStats Sentinel() {
  ArcStats a;
  a.curve = -7;
  a.begin = a.end = -9;
  a.quadrant = 99;
  return a;
}

void Scalar(const Curves& curves, const ArcParams& p, ArcOutputs* out) {
  int longest = 0;
  for (int c = 0; c < curves.size(); ++c) longest = std::max(longest, curves.offset[c + 1] - curves.offset[c]);
  std::vector<std::int32_t> stack;
  stack.reserve(2 * static_cast<std::size_t>(longest));
  scalar::Polyline(curves, PolylineToleranceQ16(p.tolerance_px), &out->polylines, &stack);
  scalar::ArcSplit(curves, out->polylines, SplitTanQ16(p.split_angle_deg), &out->splits);
  out->stats.assign(1, Sentinel());
  scalar::ArcStatsFromSplits(curves, out->splits, p.min_points, &out->stats);
}

bool SameStats(const ArcStats& p, const ArcStats& q) {
  return p.curve == q.curve && p.begin == q.begin && p.end == q.end && p.x0 == q.x0 && p.y0 == q.y0 &&
         p.x1 == q.x1 && p.y1 == q.y1 && p.xm == q.xm && p.ym == q.ym && p.min_x == q.min_x &&
         p.min_y == q.min_y && p.max_x == q.max_x && p.max_y == q.max_y && p.g0x == q.g0x && p.g0y == q.g0y &&
         p.g1x == q.g1x && p.g1y == q.g1y && p.quadrant == q.quadrant && p.sign_class == q.sign_class;
}

template <typename T>
std::string FirstDiff(const std::vector<T>& want, const std::vector<T>& got) {
  if (want.size() != got.size())
    return "sizes " + std::to_string(want.size()) + " (scalar) vs " + std::to_string(got.size()) + " (vulkan)";
  for (std::size_t i = 0; i < want.size(); ++i)
    if (want[i] != got[i])
      return "at " + std::to_string(i) + ": scalar " + std::to_string(want[i]) + ", vulkan " + std::to_string(got[i]);
  return "";
}

// Returns the number of arcs compared (so callers can assert the case exercised something).
std::size_t ExpectSame(VulkanArcStage* stage, const Curves& curves, const ArcParams& p, const std::string& what) {
  ArcOutputs want, got;
  Scalar(curves, p, &want);
  // Stale contents: Run must replace the polylines and splits and append to the stats.
  got.polylines.vertex.assign(5, -3);
  got.polylines.offset.assign(3, -3);
  got.splits.index.assign(4, -3);
  got.splits.offset.assign(2, -3);
  got.stats.assign(1, Sentinel());
  const Status st = stage->Run(curves, PolylineToleranceQ16(p.tolerance_px), SplitTanQ16(p.split_angle_deg),
                               p.min_points, &got.polylines, &got.splits, &got.stats);
  const std::string tag = what + " (tol " + std::to_string(p.tolerance_px) + ", angle " +
                          std::to_string(p.split_angle_deg) + ", min " + std::to_string(p.min_points) + ")";
  EXPECT_TRUE(st.ok()) << tag << ": " << st.message();
  if (!st.ok()) return 0;
  EXPECT_TRUE(want.polylines.vertex == got.polylines.vertex) << tag << " vertex " << FirstDiff(want.polylines.vertex, got.polylines.vertex);
  EXPECT_TRUE(want.polylines.offset == got.polylines.offset) << tag << " vertex offset " << FirstDiff(want.polylines.offset, got.polylines.offset);
  EXPECT_TRUE(want.splits.index == got.splits.index) << tag << " split " << FirstDiff(want.splits.index, got.splits.index);
  EXPECT_TRUE(want.splits.offset == got.splits.offset) << tag << " split offset " << FirstDiff(want.splits.offset, got.splits.offset);
  EXPECT_EQ(want.stats.size(), got.stats.size()) << tag << " arc count";
  const std::size_t n = std::min(want.stats.size(), got.stats.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (!SameStats(want.stats[i], got.stats[i])) {
      ADD_FAILURE() << tag << " arc " << i << " (curve " << want.stats[i].curve << ", points " << want.stats[i].begin
                    << ".." << want.stats[i].end << ") differs";
      break;
    }
  }
  return want.stats.size() - 1;
}

std::size_t ExpectSameAllParams(VulkanArcStage* stage, const Curves& curves, const std::string& what) {
  std::size_t arcs = 0;
  for (const ArcParams& p : kParamSets) arcs += ExpectSame(stage, curves, p, what);
  return arcs;
}

// Appends a curve with points (xs[i], ys[i]) and random gradients / sign class.
void AddCurve(const std::vector<std::int32_t>& xs, const std::vector<std::int32_t>& ys, std::mt19937* rng, Curves* c) {
  std::uniform_int_distribution<int> grad(-32768, 32767);
  for (std::size_t i = 0; i < xs.size(); ++i) {
    c->x.push_back(xs[i]);
    c->y.push_back(ys[i]);
    c->gx.push_back(static_cast<std::int16_t>(grad(*rng)));
    c->gy.push_back(static_cast<std::int16_t>(grad(*rng)));
  }
  c->sign_class.push_back(static_cast<std::uint8_t>(1 + (*rng)() % 2));
  c->offset.push_back(static_cast<std::int32_t>(c->x.size()));
}

// An 8-connected random walk of n points inside [lo, hi]^2 (reflecting at the borders); `turn`
// in [0, 1]: how often the direction changes.
void AddRandomWalk(int n, int lo, int hi, double turn, std::mt19937* rng, Curves* c) {
  static const int kDx[8] = {1, 1, 0, -1, -1, -1, 0, 1}, kDy[8] = {0, 1, 1, 1, 0, -1, -1, -1};
  std::uniform_int_distribution<int> pos(lo, hi);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::int32_t> xs, ys;
  int x = pos(*rng), y = pos(*rng), d = static_cast<int>((*rng)() % 8);
  for (int i = 0; i < n; ++i) {
    xs.push_back(x);
    ys.push_back(y);
    if (u(*rng) < turn) d = (d + ((*rng)() % 2 ? 1 : 7)) % 8;
    if (x + kDx[d] < lo || x + kDx[d] > hi || y + kDy[d] < lo || y + kDy[d] > hi) d = (d + 4) % 8;
    x += kDx[d];
    y += kDy[d];
  }
  AddCurve(xs, ys, rng, c);
}

void AddLine(int x0, int y0, int x1, int y1, std::mt19937* rng, Curves* c) {
  std::vector<std::int32_t> xs, ys;
  const int n = std::max(std::abs(x1 - x0), std::abs(y1 - y0));
  for (int i = 0; i <= n; ++i) {  // Bresenham-like: rounded points of the segment, 8-connected
    xs.push_back(x0 + static_cast<int>(std::lround(static_cast<double>(x1 - x0) * i / std::max(n, 1))));
    ys.push_back(y0 + static_cast<int>(std::lround(static_cast<double>(y1 - y0) * i / std::max(n, 1))));
  }
  AddCurve(xs, ys, rng, c);
}

// A zig-zag: `teeth` runs of `run` diagonal steps alternating up and down (inflections everywhere).
void AddZigZag(int x0, int y0, int run, int teeth, std::mt19937* rng, Curves* c) {
  std::vector<std::int32_t> xs, ys;
  int x = x0, y = y0;
  for (int t = 0; t < teeth; ++t) {
    for (int i = 0; i < run; ++i) {
      xs.push_back(x++);
      ys.push_back(y);
      y += (t % 2 == 0) ? 1 : -1;
    }
  }
  xs.push_back(x);
  ys.push_back(y);
  AddCurve(xs, ys, rng, c);
}

Curves Empty() {
  Curves c;
  c.clear();
  return c;
}

TEST(ConformanceVulkanArcs, RandomWalks) {
  REQUIRE_VULKAN(stage);
  for (std::uint32_t seed : {1u, 2u, 3u, 4u}) {
    std::mt19937 rng(seed);
    Curves c = Empty();
    for (int i = 0; i < 300; ++i) {
      const int n = 1 + static_cast<int>(rng() % 400);
      AddRandomWalk(n, 0, 2000, 0.05 + 0.5 * (rng() % 4) / 3.0, &rng, &c);
    }
    EXPECT_GT(ExpectSameAllParams(stage, c, "random walks seed " + std::to_string(seed)), 0u);
  }
}

TEST(ConformanceVulkanArcs, OneAndTwoPointCurves) {
  REQUIRE_VULKAN(stage);
  std::mt19937 rng(11);
  Curves c = Empty();
  AddCurve({5}, {7}, &rng, &c);
  AddCurve({5, 6}, {7, 8}, &rng, &c);
  AddCurve({16383}, {0}, &rng, &c);
  AddCurve({0, 1}, {16383, 16383}, &rng, &c);
  AddCurve({3, 3}, {3, 3}, &rng, &c);  // a repeated point: zero-length chord
  AddRandomWalk(3, 10, 20, 0.5, &rng, &c);
  ExpectSameAllParams(stage, c, "1- and 2-point curves");
  // Only the 1-point curve: one vertex, no split, one arc at min_points 1.
  Curves one = Empty();
  AddCurve({9}, {4}, &rng, &one);
  EXPECT_EQ(ExpectSame(stage, one, {1.0, 35.0, 1}, "single point"), 1u);
}

TEST(ConformanceVulkanArcs, StraightLinesAndZigZags) {
  REQUIRE_VULKAN(stage);
  std::mt19937 rng(21);
  Curves c = Empty();
  AddLine(0, 0, 100, 0, &rng, &c);
  AddLine(0, 0, 0, 100, &rng, &c);
  AddLine(10, 10, 300, 300, &rng, &c);
  AddLine(0, 0, 3000, 1000, &rng, &c);   // longer than kMaxSegmentComponent: halved by index
  AddLine(4000, 0, 0, 2500, &rng, &c);
  AddLine(0, 0, 1025, 0, &rng, &c);      // just over the halving bound
  AddLine(0, 0, 1024, 1024, &rng, &c);   // exactly at it
  for (int run : {1, 2, 3, 5, 17}) AddZigZag(0, 100, run, 40, &rng, &c);
  EXPECT_GT(ExpectSameAllParams(stage, c, "lines and zig-zags"), 0u);
}

TEST(ConformanceVulkanArcs, LongCurves) {
  REQUIRE_VULKAN(stage);
  std::mt19937 rng(31);
  Curves c = Empty();
  AddRandomWalk(5000, 0, 3000, 0.02, &rng, &c);
  AddRandomWalk(20000, 0, 5000, 0.2, &rng, &c);
  std::vector<std::int32_t> xs, ys;  // a spiral of ~9000 points (smooth, many turning splits)
  for (int i = 0; i < 9000; ++i) {
    const double t = i * 0.01, r = 50 + 0.4 * i;
    xs.push_back(4000 + static_cast<int>(std::lround(r * std::cos(t))));
    ys.push_back(4000 + static_cast<int>(std::lround(r * std::sin(t))));
  }
  AddCurve(xs, ys, &rng, &c);
  AddRandomWalk(10, 0, 100, 0.5, &rng, &c);
  EXPECT_GT(ExpectSameAllParams(stage, c, "long curves"), 0u);
  // These curves need more than one submit of rounds: the continuation path was exercised.
  EXPECT_GT(stage->last_rounds(), VulkanArcStage::kRoundsPerSubmit);
}

TEST(ConformanceVulkanArcs, CoordinatesNear16383) {
  REQUIRE_VULKAN(stage);
  std::mt19937 rng(41);
  Curves c = Empty();
  for (int i = 0; i < 50; ++i) AddRandomWalk(1 + static_cast<int>(rng() % 300), 16383 - 400, 16383, 0.2, &rng, &c);
  AddLine(0, 0, 16383, 16383, &rng, &c);
  AddLine(16383, 0, 0, 16383, &rng, &c);
  AddLine(0, 16383, 16383, 16380, &rng, &c);
  AddZigZag(16383 - 2000, 16383 - 20, 10, 150, &rng, &c);
  EXPECT_GT(ExpectSameAllParams(stage, c, "near 16383"), 0u);
}

TEST(ConformanceVulkanArcs, SizeChangesReuseAndRecreate) {
  REQUIRE_VULKAN(stage);
  std::uint32_t seed = 51;
  for (int points : {1000, 100, 70000, 100, 70000}) {
    std::mt19937 rng(seed++);
    Curves c = Empty();
    while (static_cast<int>(c.x.size()) < points) AddRandomWalk(1 + static_cast<int>(rng() % 200), 0, 1000, 0.1, &rng, &c);
    ExpectSame(stage, c, kParamSets[0], "resize to " + std::to_string(points) + " points");
    EXPECT_EQ(stage->last_rounds(), VulkanArcStage::kRoundsPerSubmit);  // short curves: one submit
  }
  // No curves at all: empty outputs, as the scalar kernels give.
  const Curves none = Empty();
  EXPECT_EQ(ExpectSame(stage, none, kParamSets[0], "no curves"), 0u);
}

TEST(ConformanceVulkanArcs, RejectsMalformedCurves) {
  REQUIRE_VULKAN(stage);
  std::mt19937 rng(61);
  Curves c = Empty();
  AddRandomWalk(5, 0, 10, 0.5, &rng, &c);
  c.offset.push_back(c.offset.back());  // an empty curve
  c.sign_class.push_back(1);
  Polylines pl;
  Splits sp;
  std::vector<ArcStats> stats;
  const Status st = stage->Run(c, 16, SplitTanQ16(35), 3, &pl, &sp, &stats);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument) << st.message();
  c.sign_class.pop_back();  // sign_class shorter than the curve count
  EXPECT_EQ(stage->Run(c, 16, SplitTanQ16(35), 3, &pl, &sp, &stats).code(), StatusCode::kInvalidArgument);
}

// The curves runtime/detector.cc fits arcs to: traced from the scalar edge stage, OBB-filtered.
Curves DatasetCurves(const cv::Mat& gray, const Options& o) {
  Curves curves = stage_test::ScalarCurves(ViewOf(gray), o, o.min_curve_points);
  std::vector<std::int64_t> hull;
  FilterCurvesByObb(o, &curves, &hull);
  return curves;
}

std::vector<std::filesystem::path> DatasetImages() {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  const fs::path root = "../shared/datasets";
  if (!fs::exists(root)) return files;
  for (const auto& set : fs::directory_iterator(root)) {
    const fs::path images = set.path() / "images";
    if (!fs::is_directory(images)) continue;
    for (const auto& f : fs::directory_iterator(images))
      if (f.is_regular_file()) files.push_back(f.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(ConformanceVulkanArcs, DatasetCurves) {
  REQUIRE_VULKAN(stage);
  int images = 0;
  std::size_t arcs = 0;
  for (const auto& f : DatasetImages()) {
    const cv::Mat gray = cv::imread(f.string(), cv::IMREAD_GRAYSCALE);
    if (gray.empty()) continue;
    const Curves curves = DatasetCurves(gray, Options());
    arcs += ExpectSameAllParams(stage, curves, f.string());
    ++images;
  }
  EXPECT_GT(images, 0) << "no readable image under ../shared/datasets (tests run from the repository root)";
  EXPECT_GT(arcs, 0u);
}

bool SameBits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

// Whole Detector runs: Backend::kVulkan (edges and arcs on the device) against kScalar.
void ExpectSameEllipses(Detector* vulkan, Detector* reference, int* images, int* ellipses) {
  for (const auto& f : DatasetImages()) {
    const cv::Mat gray = cv::imread(f.string(), cv::IMREAD_GRAYSCALE);
    if (gray.empty()) continue;
    const ImageView view = ViewOf(gray);
    DetectionResult want, got;
    ASSERT_TRUE(reference->detect(view, &want).ok()) << f;
    const Status st = vulkan->detect(view, &got);
    ASSERT_TRUE(st.ok()) << f << ": " << st.message();
    EXPECT_EQ(got.backend, Backend::kVulkan) << f;
    EXPECT_EQ(got.num_curves, want.num_curves) << f;
    EXPECT_EQ(got.num_arcs, want.num_arcs) << f;
    ASSERT_EQ(got.ellipses.size(), want.ellipses.size()) << f;
    for (std::size_t i = 0; i < want.ellipses.size(); ++i) {
      const Ellipse& p = want.ellipses[i];
      const Ellipse& q = got.ellipses[i];
      EXPECT_TRUE(SameBits(p.cx, q.cx) && SameBits(p.cy, q.cy) && SameBits(p.a, q.a) && SameBits(p.b, q.b) &&
                  SameBits(p.theta, q.theta) && SameBits(p.score, q.score))
          << f << " ellipse " << i;
    }
    ++*images;
    *ellipses += static_cast<int>(want.ellipses.size());
  }
}

TEST(ConformanceVulkanArcs, DetectorEndToEnd) {
  REQUIRE_VULKAN(stage);
  Options o;
  o.backend = Backend::kScalar;
  Detector reference(o);
  o.backend = Backend::kVulkan;
  Detector vulkan(o);
  ASSERT_TRUE(vulkan.status().ok()) << vulkan.status().message();
  int images = 0, ellipses = 0;
  ExpectSameEllipses(&vulkan, &reference, &images, &ellipses);
  EXPECT_GT(images, 0);
  EXPECT_GT(ellipses, 0);
}

// A device without shaderInt64 (simulated): the arc stage says why it is unavailable, and a
// kVulkan Detector still works, with the arcs on the CPU table and the same ellipses.
TEST(ConformanceVulkanArcs, FallbackWithoutInt64) {
  REQUIRE_VULKAN(stage);
  ASSERT_EQ(setenv("ELLIPSEKIT_VK_DISABLE_INT64", "1", 1), 0);
  std::unique_ptr<VulkanArcStage> none;
  const Status st = VulkanArcStage::Create(&none);
  Options o;
  o.backend = Backend::kVulkan;
  Detector vulkan(o);
  unsetenv("ELLIPSEKIT_VK_DISABLE_INT64");
  EXPECT_EQ(st.code(), StatusCode::kUnavailable);
  EXPECT_NE(st.message().find("shaderInt64"), std::string::npos) << st.message();
  EXPECT_EQ(none, nullptr);
  ASSERT_TRUE(vulkan.status().ok()) << vulkan.status().message();
  o.backend = Backend::kScalar;
  Detector reference(o);
  int images = 0, ellipses = 0;
  ExpectSameEllipses(&vulkan, &reference, &images, &ellipses);
  EXPECT_GT(images, 0);
}

TEST(ConformanceVulkanArcs, Timing) {
  REQUIRE_VULKAN(stage);
  const char* t = std::getenv("ELLIPSEKIT_VK_TIMING");
  if (t == nullptr || std::string(t) != "1") GTEST_SKIP() << "set ELLIPSEKIT_VK_TIMING=1 to print timings";
  using Clock = std::chrono::steady_clock;
  stage->set_timing(true);  // device_ms; the timestamps add to the wall time
  for (const auto& f : DatasetImages()) {
    const cv::Mat gray = cv::imread(f.string(), cv::IMREAD_GRAYSCALE);
    if (gray.empty()) continue;
    const Curves curves = DatasetCurves(gray, Options());
    const ArcParams p = kParamSets[0];
    ArcOutputs out;
    double best_vk = 1e30, best_dev = 1e30, best_compact = 1e30, best_scalar = 1e30;
    for (int i = 0; i < 11; ++i) {  // the first run (buffer growth) is not counted
      out.stats.clear();
      const auto a = Clock::now();
      ASSERT_TRUE(stage->Run(curves, PolylineToleranceQ16(p.tolerance_px), SplitTanQ16(p.split_angle_deg),
                             p.min_points, &out.polylines, &out.splits, &out.stats).ok());
      const auto b = Clock::now();
      if (i == 0) continue;
      best_vk = std::min(best_vk, std::chrono::duration<double, std::milli>(b - a).count());
      best_dev = std::min(best_dev, stage->last_device_ms());
      best_compact = std::min(best_compact, stage->last_compact_ms());
    }
    for (int i = 0; i < 10; ++i) {
      const auto a = Clock::now();
      Scalar(curves, p, &out);
      const auto b = Clock::now();
      best_scalar = std::min(best_scalar, std::chrono::duration<double, std::milli>(b - a).count());
    }
    std::printf("%s: %d curves, %zu points on %s: vulkan %.3f ms wall (device %.3f ms, compaction %.3f ms, "
                "%d rounds), scalar %.3f ms\n",
                f.filename().string().c_str(), curves.size(), curves.x.size(), stage->device_name().c_str(), best_vk,
                best_dev, best_compact, stage->last_rounds(), best_scalar);
  }
  stage->set_timing(false);
}

}  // namespace
}  // namespace ellipsekit

#else  // !ELLIPSEKIT_HAVE_VULKAN

TEST(ConformanceVulkanArcs, NotBuilt) {
  GTEST_SKIP() << "ellipsekit was built without the Vulkan backend (ELLIPSEKIT_HAVE_VULKAN unset)";
}

#endif
