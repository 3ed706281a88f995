// Bounded worst case (DESIGN.md "Bounded work"): adversarial 1920x1080 frames finish within 10x the
// median time of a generated scene of the same size, and the result says which cap was hit.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "ellipsekit/ellipsekit.h"
#include "tools/scenes/scene_generator.h"

namespace ellipsekit {
namespace {

constexpr int kW = 1920, kH = 1080;
constexpr double kMaxRatio = 10.0;

// Sanitizers slow code down unevenly (ASan most where memory traffic is densest), so a time ratio
// measured under them says nothing about the product: there the ratios are printed, not asserted.
// The caps are asserted in every build.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kAssertTime = false;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
constexpr bool kAssertTime = false;
#else
constexpr bool kAssertTime = true;
#endif
#else
constexpr bool kAssertTime = true;
#endif

ImageView ViewOf(const cv::Mat& m) {
  return {m.ptr<std::uint8_t>(), m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step[0])};
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Best (shortest) wall time of `runs` detections, ms; `last` holds the last result. The best of a
// few runs measures the work done, not what the shared machine's other processes took from it.
double TimeDetect(Detector* det, const cv::Mat& img, int runs, DetectionResult* last) {
  std::vector<double> ms;
  for (int i = 0; i < runs; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    const Status st = det->detect(ViewOf(img), last);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    EXPECT_TRUE(st.ok()) << st.message();
  }
  return *std::min_element(ms.begin(), ms.end());
}

cv::Mat Noise() {
  cv::Mat m(kH, kW, CV_8UC1);
  std::mt19937 rng(1234);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) m.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(rng() >> 24);
  return m;
}

cv::Mat Checkerboard(int cell) {
  cv::Mat m(kH, kW, CV_8UC1);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) m.at<std::uint8_t>(y, x) = ((x / cell + y / cell) & 1) ? 220 : 30;
  return m;
}

cv::Mat ConcentricCircles(int count) {
  cv::Mat m(kH, kW, CV_8UC1, cv::Scalar(60));
  for (int i = 0; i < count; ++i)
    cv::circle(m, cv::Point(kW / 2, kH / 2), 4 + 5 * i, cv::Scalar(i % 2 ? 230 : 10), 2, cv::LINE_AA);
  return m;
}

cv::Mat RandomSegments(int count) {
  cv::Mat m(kH, kW, CV_8UC1, cv::Scalar(100));
  std::mt19937 rng(99);
  std::uniform_int_distribution<int> x(0, kW - 1), y(0, kH - 1), g(0, 255), t(1, 3);
  for (int i = 0; i < count; ++i)
    cv::line(m, cv::Point(x(rng), y(rng)), cv::Point(x(rng), y(rng)), cv::Scalar(g(rng)), t(rng), cv::LINE_AA);
  return m;
}

std::string CapNames(unsigned caps) {
  std::string s;
  for (const CapFlags bit : kAllCaps)
    if (caps & bit) s += (s.empty() ? "" : "+") + std::string(CapName(bit));
  return s.empty() ? "none" : s;
}

// Median detect() time of generated 1920x1080 scenes, per backend, measured once.
double SceneMedianMs(Detector* det) {
  std::vector<double> ms;
  DetectionResult r;
  for (std::uint64_t seed = 1; seed <= 7; ++seed) {
    scenes::SceneOptions so;
    so.width = kW;
    so.height = kH;
    const scenes::Scene s = scenes::RenderScene(seed, so);
    EXPECT_FALSE(s.gray.empty());
    if (seed == 1) TimeDetect(det, s.gray, 1, &r);  // first frame of this size allocates
    ms.push_back(TimeDetect(det, s.gray, 2, &r));
  }
  return Median(ms);
}

struct Case {
  const char* name;
  cv::Mat (*make)();
  unsigned caps;  // the caps the default options hit on it (measured; the same on every backend)
};

// Measured (scalar and auto): noise 406 arcs, 78 candidates (11 in the first pass, 67 in the crowd
// pass; its noise reads 63, the estimate's clamp, so it is smoothed twice: blobs with outlines;
// 160 arcs and 0 candidates unsmoothed); the checkerboards no arcs;
// concentric_200 790 arcs, 82 candidates, pairs, triplets and the outer-rim search capped (39
// candidates and no rim-search cap before fit_pair_centers); segments_2000 1427 arcs, 202
// candidates, no cap.
const Case kCases[] = {
    {"noise", [] { return Noise(); }, kCapNone},
    {"checkerboard_4px", [] { return Checkerboard(4); }, kCapNone},
    {"checkerboard_1px", [] { return Checkerboard(1); }, kCapNone},
    {"concentric_200", [] { return ConcentricCircles(200); }, kCapPairs | kCapTriplets | kCapRimSearch},
    {"segments_2000", [] { return RandomSegments(2000); }, kCapNone},
};

class WorstCase : public ::testing::TestWithParam<Backend> {};

TEST_P(WorstCase, WithinTenTimesASceneAndCapsReported) {
  Options o;
  o.backend = GetParam();
  Detector det(o);
  if (det.status().code() == StatusCode::kUnavailable) GTEST_SKIP() << det.status().message();
  ASSERT_TRUE(det.status().ok()) << det.status().message();
  const double scene_ms = SceneMedianMs(&det);
  std::printf("[worst case] backend %s: scene median %.1f ms\n", BackendName(GetParam()), scene_ms);
  int candidate_cap_frames = 0;
  for (const Case& c : kCases) {
    const cv::Mat img = c.make();
    DetectionResult r;
    const double ms = TimeDetect(&det, img, 3, &r);
    const double ratio = ms / scene_ms;
    std::printf("[worst case] %-18s %8.1f ms  ratio %5.2f  caps_hit %-28s arcs %d candidates %d ellipses %zu\n",
                c.name, ms, ratio, CapNames(r.caps_hit).c_str(), r.num_arcs, r.num_candidates, r.ellipses.size());
    RecordProperty(std::string(c.name) + "_ratio", std::to_string(ratio));
    if (kAssertTime) EXPECT_LT(ratio, kMaxRatio) << c.name << ": " << ms << " ms vs scene median " << scene_ms << " ms";
    // The counts never exceed the caps, and reaching a cap is reported.
    EXPECT_LE(r.num_arcs, o.max_arcs) << c.name;
    EXPECT_LE(r.num_candidates, o.max_candidates) << c.name;
    // The result names exactly the caps this frame reaches.
    EXPECT_EQ(r.caps_hit, c.caps) << c.name << ": caps_hit " << CapNames(r.caps_hit) << ", measured "
                                  << CapNames(c.caps);
    // No frame reaches the default candidate cap (10000), so the candidate cap is set to half of what
    // the frame produces, which it must then reach, report, and hold. Measured on one back-end pass:
    // the crowd pass (it runs on the smoothed noise frame: 11 + 67 candidates) is a second pass
    // with a cap of its own (DetectionResult::num_candidates).
    Options single = o;
    single.crowd_min_curve_points = single.min_curve_points;  // no crowd pass
    DetectionResult rs;
    ASSERT_TRUE(Detector(single).detect(ViewOf(img), &rs).ok()) << c.name;
    if (rs.num_candidates < 2) continue;
    ++candidate_cap_frames;
    Options capped = single;
    capped.max_candidates = rs.num_candidates / 2;
    Detector capped_det(capped);
    DetectionResult rc;
    ASSERT_TRUE(capped_det.detect(ViewOf(img), &rc).ok()) << c.name;
    std::printf("[worst case] %-18s max_candidates %d: caps_hit %s candidates %d ellipses %zu\n", c.name,
                capped.max_candidates, CapNames(rc.caps_hit).c_str(), rc.num_candidates, rc.ellipses.size());
    EXPECT_TRUE(rc.caps_hit & kCapCandidates) << c.name << ": caps_hit " << CapNames(rc.caps_hit);
    EXPECT_EQ(rc.num_candidates, capped.max_candidates) << c.name;
  }
  // noise, concentric_200 and segments_2000 have candidates (11, 82 and 202 on one pass).
  EXPECT_EQ(candidate_cap_frames, 3);
}

INSTANTIATE_TEST_SUITE_P(Backends, WorstCase, ::testing::Values(Backend::kScalar, Backend::kAuto),
                         [](const auto& info) { return std::string(BackendName(info.param)); });

// Each cap, set low on a frame with many arcs and candidates, is reported by its own flag and bounds its count.
TEST(WorstCaseCaps, EachLowCapIsReported) {
  // A busy generated scene: many arcs and several candidates (the concentric-circle frame hits the
  // triplet cap before it produces any candidate, so it cannot exercise the candidate cap).
  scenes::SceneOptions so;
  so.min_objects = so.max_objects = 5;
  so.clutter_shapes = 12;
  const cv::Mat img = scenes::RenderScene(21, so).gray;
  struct CapCase {
    const char* name;
    unsigned flag;
    void (*set)(Options*);
  };
  const CapCase cases[] = {
      {"max_arcs", kCapArcs, [](Options* o) { o->max_arcs = 8; }},
      {"max_pairs", kCapPairs, [](Options* o) { o->max_pairs = 4; }},
      {"max_triplets", kCapTriplets, [](Options* o) { o->max_triplets = 2; }},
      {"max_candidates", kCapCandidates, [](Options* o) { o->max_candidates = 1; }},
      // The mean shift (Fig. 7) runs only where eqs. 8-12 need its centre: on the paper's path,
      // without the refit. Uncapped (20 iterations) that path reaches no cap on this frame (below).
      {"max_mean_shift_iterations", kCapMeanShift, [](Options* o) { o->refine_fit = false; o->max_mean_shift_iterations = 1; }},
  };
  Detector reference;
  DetectionResult full;
  ASSERT_TRUE(reference.detect(ViewOf(img), &full).ok());
  std::printf("[caps] uncapped: arcs %d candidates %d ellipses %zu caps_hit %s\n", full.num_arcs,
              full.num_candidates, full.ellipses.size(), CapNames(full.caps_hit).c_str());
  ASSERT_GT(full.num_arcs, 8);
  ASSERT_GT(full.num_candidates, 1);
  for (const CapCase& c : cases) {
    Options o;
    c.set(&o);
    Detector det(o);
    DetectionResult r;
    ASSERT_TRUE(det.detect(ViewOf(img), &r).ok()) << c.name;
    std::printf("[caps] %-15s caps_hit %-30s arcs %d candidates %d ellipses %zu\n", c.name,
                CapNames(r.caps_hit).c_str(), r.num_arcs, r.num_candidates, r.ellipses.size());
    EXPECT_TRUE(r.caps_hit & c.flag) << c.name << ": caps_hit " << CapNames(r.caps_hit);
    EXPECT_LE(r.num_arcs, o.max_arcs) << c.name;
    EXPECT_LE(r.num_candidates, o.max_candidates) << c.name;
  }
  // The paper's path with the default mean-shift cap reaches no cap on the busy frame, so the flag
  // above comes from max_mean_shift_iterations = 1.
  Options paper;
  paper.refine_fit = false;
  DetectionResult paper_result;
  ASSERT_TRUE(Detector(paper).detect(ViewOf(img), &paper_result).ok());
  EXPECT_EQ(paper_result.caps_hit, 0u) << CapNames(paper_result.caps_hit);
  // The uncapped frame of a plain scene reports no cap.
  const scenes::Scene s = scenes::RenderScene(3);
  DetectionResult plain;
  ASSERT_TRUE(reference.detect(ViewOf(s.gray), &plain).ok());
  EXPECT_EQ(plain.caps_hit, 0u) << CapNames(plain.caps_hit);
}

}  // namespace
}  // namespace ellipsekit
