// API hardening beyond test_detector_errors.cc: enumerators outside their range, moved-from
// detectors, views whose buffer ends exactly at the last pixel, extreme shapes and strides, frame
// size changes, extreme but valid options. Nothing may crash, and every error names its problem.
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "ellipsekit/ellipsekit.h"
#include "tools/scenes/scene_generator.h"

namespace ellipsekit {
namespace {

bool Mentions(const Status& st, const std::string& word) { return st.message().find(word) != std::string::npos; }

ImageView ViewOf(const cv::Mat& m) {
  return {m.ptr<std::uint8_t>(), m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step[0])};
}

std::vector<Backend> Backends() { return {Backend::kScalar, Backend::kSimd, Backend::kVulkan}; }

void ExpectSameEllipses(const DetectionResult& a, const DetectionResult& b, const std::string& what) {
  ASSERT_EQ(a.ellipses.size(), b.ellipses.size()) << what;
  for (std::size_t i = 0; i < a.ellipses.size(); ++i) {
    EXPECT_EQ(std::memcmp(&a.ellipses[i], &b.ellipses[i], sizeof(Ellipse)), 0) << what << ", ellipse " << i;
  }
  EXPECT_EQ(a.num_edge_pixels, b.num_edge_pixels) << what;
  EXPECT_EQ(a.num_arcs, b.num_arcs) << what;
  EXPECT_EQ(a.caps_hit, b.caps_hit) << what;
}

// Enumerators outside their range are refused by name (only `backend` is checked by ValidateOptions
// in test_detector_errors.cc); a switch over them would otherwise be undefined behaviour.
TEST(RobustnessApi, OutOfRangeEnumeratorsAreNamed) {
  struct Case {
    const char* keyword;
    void (*set)(Options*);
  };
  const Case cases[] = {
      {"obb_rule", [](Options* o) { o->obb_rule = static_cast<ObbRule>(7); }},
      {"center_method", [](Options* o) { o->center_method = static_cast<CenterMethod>(-1); }},
      {"inlier_rule", [](Options* o) { o->inlier_rule = static_cast<InlierRule>(9); }},
      {"cluster_rule", [](Options* o) { o->cluster_rule = static_cast<ClusterRule>(3); }},
  };
  for (const Case& c : cases) {
    Options o;
    c.set(&o);
    const Status st = ValidateOptions(o);
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument) << c.keyword;
    EXPECT_TRUE(Mentions(st, c.keyword)) << c.keyword << ": '" << st.message() << "'";
  }
}

// A moved-from Detector must report an error instead of dereferencing its moved-out state.
TEST(RobustnessApi, MovedFromDetectorReportsAnError) {
  Detector a;
  Detector b(std::move(a));
  std::vector<std::uint8_t> buf(32 * 32, 7);
  DetectionResult r;
  EXPECT_TRUE(b.detect({buf.data(), 32, 32, 32}, &r).ok());
  // NOLINTNEXTLINE(bugprone-use-after-move): the point of the test
  const Status st = a.detect({buf.data(), 32, 32, 32}, &r);
  EXPECT_FALSE(st.ok());
  EXPECT_FALSE(st.message().empty());
  EXPECT_FALSE(a.status().ok());
}

// The view's buffer ends exactly at its last pixel ((h - 1) * stride + w bytes): nothing may read past
// it (AddressSanitizer catches it under --sanitize), and a padded stride gives the same result as a
// compact copy, on every backend.
TEST(RobustnessApi, ExactBuffersAndPaddedStrides) {
  const scenes::Scene s = scenes::RenderScene(11);
  const int w = s.gray.cols, h = s.gray.rows;
  for (Backend b : Backends()) {
    Options o;
    o.backend = b;
    Detector det(o);
    if (det.status().code() == StatusCode::kUnavailable) continue;
    ASSERT_TRUE(det.status().ok()) << det.status().message();
    DetectionResult compact;
    {
      auto buf = std::make_unique<std::uint8_t[]>(static_cast<std::size_t>(w) * h);
      for (int y = 0; y < h; ++y) std::memcpy(buf.get() + static_cast<std::size_t>(y) * w, s.gray.ptr(y), w);
      ASSERT_TRUE(det.detect({buf.get(), w, h, w}, &compact).ok());
    }
    EXPECT_FALSE(compact.ellipses.empty()) << BackendName(b);
    for (std::ptrdiff_t stride : {std::ptrdiff_t{w + 1}, std::ptrdiff_t{w + 13}, std::ptrdiff_t{w + 64}, std::ptrdiff_t{3 * w}}) {
      const std::size_t size = static_cast<std::size_t>(h - 1) * stride + w;
      auto buf = std::make_unique<std::uint8_t[]>(size);
      std::memset(buf.get(), 0xA5, size);  // padding with a loud value: it must not be read as pixels
      for (int y = 0; y < h; ++y) std::memcpy(buf.get() + y * stride, s.gray.ptr(y), w);
      DetectionResult padded;
      ASSERT_TRUE(det.detect({buf.get(), w, h, stride}, &padded).ok());
      ExpectSameEllipses(compact, padded, std::string(BackendName(b)) + " stride " + std::to_string(stride));
    }
  }
}

// Degenerate and extreme shapes: valid ones run and find nothing, too large ones are refused by name.
TEST(RobustnessApi, ExtremeShapes) {
  for (Backend b : Backends()) {
    Options o;
    o.backend = b;
    Detector det(o);
    if (det.status().code() == StatusCode::kUnavailable) continue;
    const std::pair<int, int> ok_shapes[] = {{1, 1}, {2, 2}, {3, 1}, {1, 3}, {16384, 1}, {1, 16384}, {16384, 3}, {3, 16384}};
    for (auto [w, h] : ok_shapes) {
      std::vector<std::uint8_t> buf(static_cast<std::size_t>(w) * h);
      std::mt19937 rng(w * 31 + h);
      for (auto& v : buf) v = static_cast<std::uint8_t>(rng());
      DetectionResult r;
      const Status st = det.detect({buf.data(), w, h, w}, &r);
      EXPECT_TRUE(st.ok()) << BackendName(b) << " " << w << "x" << h << ": " << st.message();
      EXPECT_TRUE(r.ellipses.empty()) << BackendName(b) << " " << w << "x" << h;
    }
    std::vector<std::uint8_t> row(65536, 9);
    DetectionResult r;
    Status st = det.detect({row.data(), 65536, 1, 65536}, &r);
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
    EXPECT_TRUE(Mentions(st, "65536x1")) << st.message();
    EXPECT_TRUE(Mentions(st, "16384")) << st.message();
    // A huge stride over a 2-row frame: only the two rows are read.
    const std::ptrdiff_t stride = 1 << 22;
    auto big = std::make_unique<std::uint8_t[]>(stride + 8);
    std::memset(big.get(), 50, stride + 8);
    st = det.detect({big.get(), 8, 2, stride}, &r);
    EXPECT_TRUE(st.ok()) << st.message();
    // Overflow-prone sizes are refused, not wrapped.
    st = det.detect({row.data(), INT_MAX, INT_MAX, PTRDIFF_MAX}, &r);
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
    st = det.detect({row.data(), 4, 4, PTRDIFF_MIN}, &r);
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
    EXPECT_TRUE(Mentions(st, "stride")) << st.message();
  }
}

// Changing the frame size between calls gives the same result as a fresh detector, and a later
// frame without ellipses clears the previous ones: on every backend (a size change re-creates the
// SIMD planes and the Vulkan buffers), each result also equal to the scalar reference's.
TEST(RobustnessApi, FrameSizeChangesAndStaleResults) {
  scenes::SceneOptions small;
  small.width = 200;
  small.height = 150;
  scenes::SceneOptions wide;
  wide.width = 960;
  wide.height = 540;
  const scenes::Scene a = scenes::RenderScene(5), b = scenes::RenderScene(6, small), c = scenes::RenderScene(7, wide);
  Options scalar_options;
  scalar_options.backend = Backend::kScalar;
  DetectionResult want_a, want_b, want_c;
  ASSERT_TRUE(Detector(scalar_options).detect(ViewOf(a.gray), &want_a).ok());
  ASSERT_TRUE(Detector(scalar_options).detect(ViewOf(b.gray), &want_b).ok());
  ASSERT_TRUE(Detector(scalar_options).detect(ViewOf(c.gray), &want_c).ok());
  ASSERT_FALSE(want_a.ellipses.empty());
  ASSERT_FALSE(want_b.ellipses.empty());
  ASSERT_FALSE(want_c.ellipses.empty());
  int ran = 0;
  for (Backend backend : Backends()) {
    Options o;
    o.backend = backend;
    Detector det(o);
    if (det.status().code() == StatusCode::kUnavailable) {
      std::printf("[size changes] %s unavailable: %s\n", BackendName(backend), det.status().message().c_str());
      continue;
    }
    ASSERT_TRUE(det.status().ok()) << BackendName(backend) << ": " << det.status().message();
    ++ran;
    const std::string name = BackendName(backend);
    // 640x480 -> 200x150 (smaller) -> 960x540 (larger) -> 640x480 again.
    DetectionResult ra, rb, rc, ra2;
    ASSERT_TRUE(det.detect(ViewOf(a.gray), &ra).ok()) << name;
    ASSERT_TRUE(det.detect(ViewOf(b.gray), &rb).ok()) << name;
    ASSERT_TRUE(det.detect(ViewOf(c.gray), &rc).ok()) << name;
    ASSERT_TRUE(det.detect(ViewOf(a.gray), &ra2).ok()) << name;
    EXPECT_EQ(ra2.backend, backend) << name;
    DetectionResult fresh_b;
    ASSERT_TRUE(Detector(o).detect(ViewOf(b.gray), &fresh_b).ok()) << name;
    ExpectSameEllipses(fresh_b, rb, name + ": smaller frame vs a fresh detector");
    ExpectSameEllipses(want_a, ra, name + ": first frame vs scalar");
    ExpectSameEllipses(want_b, rb, name + ": smaller frame vs scalar");
    ExpectSameEllipses(want_c, rc, name + ": larger frame vs scalar");
    ExpectSameEllipses(want_a, ra2, name + ": back to the first size vs scalar");
    const cv::Mat flat(a.gray.rows, a.gray.cols, CV_8UC1, cv::Scalar(255));
    ASSERT_TRUE(det.detect(ViewOf(flat), &ra2).ok()) << name;
    EXPECT_TRUE(ra2.ellipses.empty()) << name;
    EXPECT_EQ(ra2.num_edge_pixels, 0) << name;
    EXPECT_EQ(ra2.caps_hit, 0u) << name;
  }
#if defined(ELLIPSEKIT_HAVE_SIMD)
  EXPECT_GE(ran, 2) << "scalar and SIMD at least";
#else
  EXPECT_GE(ran, 1);
#endif
}

// Extreme but valid options run and return finite, consistent ellipses.
TEST(RobustnessApi, ExtremeValidOptions) {
  const scenes::Scene s = scenes::RenderScene(8);
  const std::vector<std::pair<const char*, void (*)(Options*)>> cases = {
      {"all caps 1", [](Options* o) { o->max_arcs = o->max_pairs = o->max_triplets = o->max_candidates = o->max_mean_shift_iterations = 1; }},
      {"max_arcs INT_MAX", [](Options* o) { o->max_arcs = INT_MAX; }},
      {"max_pairs INT_MAX", [](Options* o) { o->max_pairs = INT_MAX; }},
      {"max_triplets INT_MAX", [](Options* o) { o->max_triplets = INT_MAX; }},
      {"max_candidates INT_MAX", [](Options* o) { o->max_candidates = INT_MAX; }},
      {"max_mean_shift_iterations INT_MAX", [](Options* o) { o->max_mean_shift_iterations = INT_MAX; }},
      {"max_image_pixels INT_MAX", [](Options* o) { o->max_image_pixels = INT_MAX; }},
      {"thresholds 0", [](Options* o) { o->canny_high_permille = 0; o->canny_low_permille = 0; o->canny_min_high = 0; }},
      {"thresholds max", [](Options* o) { o->canny_high_permille = 1000; o->canny_low_permille = 1000; o->canny_min_high = 2040; }},
      {"huge distances", [](Options* o) { o->center_distance = 1e300; o->mean_shift_bandwidth = 1e300; o->distance_ratio = 1e300; o->cluster_distance = 1e300; o->inlier_threshold = 1e300; }},
      {"tiny distances", [](Options* o) { o->center_distance = 1e-300; o->mean_shift_bandwidth = 1e-300; o->inlier_threshold = 1e-300; }},
      {"loose", [](Options* o) { o->min_curve_points = 3; o->obb_threshold = 0; o->polyline_tolerance = 4; o->split_angle_deg = 60; o->length_ratio = 0; o->circumference_ratio = 0; o->refined_circumference_ratio = 0; }},
      {"coverage checks off", [](Options* o) { o->min_edge_coverage = 0; o->rim_min_coverage = 1e300; }},
      {"coverage 1", [](Options* o) { o->min_edge_coverage = 1; o->rim_min_coverage = 0; }},
      {"negative margin", [](Options* o) { o->cluster_outer_margin = -1e9; o->cluster_rule = ClusterRule::kRelative; o->cluster_relative = 1; }},
      {"arc chords algebraic", [](Options* o) { o->center_method = CenterMethod::kArcChords; o->inlier_rule = InlierRule::kAlgebraic; o->obb_rule = ObbRule::kSideRatio; o->obb_threshold = 1e300; }},
  };
  for (const auto& [name, set] : cases) {
    Options o;
    o.backend = Backend::kScalar;
    set(&o);
    ASSERT_TRUE(ValidateOptions(o).ok()) << name << ": " << ValidateOptions(o).message();
    Detector det(o);
    DetectionResult r;
    const Status st = det.detect(ViewOf(s.gray), &r);
    EXPECT_TRUE(st.ok()) << name << ": " << st.message();
    if (!st.ok()) continue;
    EXPECT_LE(r.num_arcs, o.max_arcs) << name;
    EXPECT_LE(r.num_candidates, o.max_candidates) << name;
    for (const Ellipse& e : r.ellipses) {
      EXPECT_TRUE(std::isfinite(e.cx) && std::isfinite(e.cy) && std::isfinite(e.a) && std::isfinite(e.b) &&
                  std::isfinite(e.theta) && std::isfinite(e.score)) << name;
      EXPECT_GT(e.b, 0) << name;
      EXPECT_GE(e.a, e.b) << name;
      EXPECT_GE(e.theta, -M_PI / 2 - 1e-9) << name;
      EXPECT_LT(e.theta, M_PI / 2 + 1e-9) << name;
    }
  }
}

// Every cap has its own non-empty name (the CLI's caps_hit list and logs print them); other
// values have none.
TEST(RobustnessApi, CapNamesAreDistinct) {
  std::vector<std::string> names;
  unsigned all = 0;
  for (const CapFlags cap : kAllCaps) {
    const std::string name = CapName(cap);
    EXPECT_FALSE(name.empty()) << cap;
    for (const std::string& other : names) EXPECT_NE(name, other);
    names.push_back(name);
    EXPECT_EQ(all & cap, 0u) << "flags are distinct bits";
    all |= cap;
  }
  EXPECT_STREQ(CapName(kCapNone), "");
  EXPECT_STREQ(CapName(static_cast<CapFlags>(1u << 31)), "");
}

}  // namespace
}  // namespace ellipsekit
