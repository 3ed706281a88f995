// Bad inputs and edge cases of the public API: every error is a non-ok Status naming the problem.
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ellipsekit/ellipsekit.h"

namespace ellipsekit {
namespace {

bool Mentions(const Status& st, const std::string& word) { return st.message().find(word) != std::string::npos; }

// A bright ellipse on a dark ground, drawn by inside test (no OpenCV needed).
std::vector<std::uint8_t> EllipseImage(int w, int h, std::ptrdiff_t stride, std::uint8_t pad) {
  std::vector<std::uint8_t> img(static_cast<std::size_t>(stride) * h, pad);
  const double cx = w * 0.45, cy = h * 0.55, a = w * 0.3, b = h * 0.25, th = 0.4;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const double dx = x - cx, dy = y - cy;
      const double u = dx * std::cos(th) + dy * std::sin(th), v = -dx * std::sin(th) + dy * std::cos(th);
      img[static_cast<std::size_t>(y) * stride + x] = (u * u / (a * a) + v * v / (b * b) <= 1) ? 200 : 40;
    }
  }
  return img;
}

TEST(DetectorErrors, BadImageViews) {
  Detector det;
  ASSERT_TRUE(det.status().ok());
  DetectionResult r;
  std::vector<std::uint8_t> buf(64 * 64, 0);
  Status st = det.detect({nullptr, 64, 64, 64}, &r);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(Mentions(st, "null")) << st.message();
  for (auto [w, h] : {std::pair{0, 64}, {64, 0}, {-1, 64}, {64, -5}}) {
    st = det.detect({buf.data(), w, h, 64}, &r);
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
    EXPECT_TRUE(Mentions(st, "not positive")) << st.message();
  }
  st = det.detect({buf.data(), 64, 64, 63}, &r);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(Mentions(st, "stride")) << st.message();
  // A stride whose rows would run past the address range is refused, not followed (it crashed).
  for (std::ptrdiff_t stride : {PTRDIFF_MAX, PTRDIFF_MAX / 2, PTRDIFF_MAX / 3 + 1}) {
    st = det.detect({buf.data(), 4, 4, stride}, &r);
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument) << stride;
    EXPECT_TRUE(Mentions(st, "overflows")) << st.message();
  }
  // A side over 16384 px is refused before the data is touched (one row only here).
  std::vector<std::uint8_t> row(16385, 0);
  st = det.detect({row.data(), 16385, 1, 16385}, &r);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(Mentions(st, "16384")) << st.message();
  st = det.detect({row.data(), 1, 16385, 1}, &r);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  // max_image_pixels.
  Options o;
  o.max_image_pixels = 1000;
  Detector small(o);
  st = small.detect({buf.data(), 64, 64, 64}, &r);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(Mentions(st, "max_image_pixels")) << st.message();
  EXPECT_TRUE(small.detect({buf.data(), 20, 50, 64}, &r).ok());
  // Null result.
  st = det.detect({buf.data(), 64, 64, 64}, nullptr);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(Mentions(st, "result")) << st.message();
}

struct BadOption {
  const char* keyword;
  std::function<void(Options*)> set;
};

TEST(DetectorErrors, EachInvalidOptionIsNamed) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<BadOption> cases = {
      {"canny_high_permille", [](Options* o) { o->canny_high_permille = -1; }},
      {"canny_high_permille", [](Options* o) { o->canny_high_permille = 1001; }},
      {"canny_low_permille", [](Options* o) { o->canny_low_permille = 1001; }},
      {"canny_min_high", [](Options* o) { o->canny_min_high = -3; }},
      {"canny_min_high", [](Options* o) { o->canny_min_high = 5000; }},
      {"canny_contrast_ref", [](Options* o) { o->canny_contrast_ref = -1; }},
      {"canny_contrast_ref", [](Options* o) { o->canny_contrast_ref = 2041; }},
      {"canny_tile", [](Options* o) { o->canny_tile = -1; }},
      {"canny_tile", [](Options* o) { o->canny_tile = 16; }},
      {"canny_tile", [](Options* o) { o->canny_tile = 48; }},
      {"canny_tile", [](Options* o) { o->canny_tile = 32768; }},
      {"min_curve_points", [](Options* o) { o->min_curve_points = 2; }},
      {"obb_threshold", [&](Options* o) { o->obb_threshold = nan; }},
      {"obb_threshold", [](Options* o) { o->obb_threshold = -1; }},
      {"polyline_tolerance", [](Options* o) { o->polyline_tolerance = 0; }},
      {"polyline_tolerance", [](Options* o) { o->polyline_tolerance = 4.5; }},
      {"split_angle_deg", [&](Options* o) { o->split_angle_deg = nan; }},
      {"split_angle_deg", [](Options* o) { o->split_angle_deg = 0; }},
      {"split_angle_deg", [](Options* o) { o->split_angle_deg = 61; }},
      {"center_distance", [](Options* o) { o->center_distance = -2; }},
      {"center_distance", [&](Options* o) { o->center_distance = inf; }},
      {"mean_shift_bandwidth", [](Options* o) { o->mean_shift_bandwidth = 0; }},
      {"distance_ratio", [](Options* o) { o->distance_ratio = 0.5; }},
      {"length_ratio", [](Options* o) { o->length_ratio = -0.1; }},
      {"length_ratio", [&](Options* o) { o->length_ratio = nan; }},
      {"inlier_threshold", [](Options* o) { o->inlier_threshold = 0; }},
      {"circumference_ratio", [](Options* o) { o->circumference_ratio = 1.5; }},
      {"circumference_ratio", [&](Options* o) { o->circumference_ratio = nan; }},
      {"refined_circumference_ratio", [](Options* o) { o->refined_circumference_ratio = -0.5; }},
      {"cluster_distance", [](Options* o) { o->cluster_distance = -1; }},
      {"cluster_relative", [](Options* o) { o->cluster_relative = 2; }},
      {"min_edge_coverage", [](Options* o) { o->min_edge_coverage = 1.5; }},
      {"min_edge_coverage", [&](Options* o) { o->min_edge_coverage = nan; }},
      {"min_exclusive_coverage", [](Options* o) { o->min_exclusive_coverage = 1.1; }},
      {"max_striped_share", [](Options* o) { o->max_striped_share = -0.1; }},
      {"max_striped_share", [&](Options* o) { o->max_striped_share = nan; }},
      {"max_nested_striped_share", [](Options* o) { o->max_nested_striped_share = 1.5; }},
      {"pair_min_edge_coverage", [&](Options* o) { o->pair_min_edge_coverage = nan; }},
      {"rescue_min_coverage", [](Options* o) { o->rescue_min_coverage = -0.1; }},
      {"rescue_min_coverage", [&](Options* o) { o->rescue_min_coverage = nan; }},
      {"min_axis_ratio", [](Options* o) { o->min_axis_ratio = -0.1; }},
      {"min_axis_ratio", [](Options* o) { o->min_axis_ratio = 2; }},
      {"rim_min_coverage", [](Options* o) { o->rim_min_coverage = -0.5; }},
      {"rim_min_coverage", [&](Options* o) { o->rim_min_coverage = nan; }},
      {"max_arcs", [](Options* o) { o->max_arcs = 0; }},
      {"max_pairs", [](Options* o) { o->max_pairs = -1; }},
      {"max_triplets", [](Options* o) { o->max_triplets = 0; }},
      {"max_candidates", [](Options* o) { o->max_candidates = 0; }},
      {"max_mean_shift_iterations", [](Options* o) { o->max_mean_shift_iterations = 0; }},
      {"max_image_pixels", [](Options* o) { o->max_image_pixels = 0; }},
      {"backend", [](Options* o) { o->backend = static_cast<Backend>(17); }},
  };
  EXPECT_TRUE(ValidateOptions(Options()).ok());
  std::vector<std::uint8_t> buf(32 * 32, 100);
  for (const BadOption& c : cases) {
    Options o;
    c.set(&o);
    const Status st = ValidateOptions(o);
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument) << c.keyword;
    EXPECT_TRUE(Mentions(st, c.keyword)) << c.keyword << ": " << st.message();
    // The detector reports the same error from status() and every detect().
    Detector det(o);
    EXPECT_EQ(det.status().code(), StatusCode::kInvalidArgument) << c.keyword;
    DetectionResult r;
    const Status ds = det.detect({buf.data(), 32, 32, 32}, &r);
    EXPECT_EQ(ds.code(), StatusCode::kInvalidArgument) << c.keyword;
    EXPECT_EQ(ds.message(), st.message());
  }
}

TEST(DetectorErrors, SetOption) {
  Options o;
  EXPECT_TRUE(SetOption("split_angle_deg=30", &o).ok());
  EXPECT_EQ(o.split_angle_deg, 30);
  EXPECT_TRUE(SetOption("inlier_rule=algebraic", &o).ok());
  EXPECT_EQ(o.inlier_rule, InlierRule::kAlgebraic);
  EXPECT_TRUE(SetOption("refine_fit=false", &o).ok());
  EXPECT_FALSE(o.refine_fit);
  EXPECT_TRUE(SetOption("backend=scalar", &o).ok());
  EXPECT_EQ(o.backend, Backend::kScalar);
  EXPECT_TRUE(SetOption("max_arcs=12", &o).ok());
  EXPECT_EQ(o.max_arcs, 12);
  EXPECT_TRUE(SetOption("pair_candidates=false", &o).ok());
  EXPECT_FALSE(o.pair_candidates);
  EXPECT_TRUE(SetOption("cluster_pick_best_fit=false", &o).ok());
  EXPECT_FALSE(o.cluster_pick_best_fit);
  EXPECT_TRUE(SetOption("min_exclusive_coverage=0.25", &o).ok());
  EXPECT_EQ(o.min_exclusive_coverage, 0.25);
  EXPECT_TRUE(SetOption("max_striped_share=1", &o).ok());
  EXPECT_EQ(o.max_striped_share, 1);
  EXPECT_TRUE(SetOption("max_nested_striped_share=0.5", &o).ok());
  EXPECT_EQ(o.max_nested_striped_share, 0.5);
  EXPECT_TRUE(SetOption("pair_min_edge_coverage=0.8", &o).ok());
  EXPECT_EQ(o.pair_min_edge_coverage, 0.8);
  EXPECT_TRUE(SetOption("min_axis_ratio=0", &o).ok());
  EXPECT_EQ(o.min_axis_ratio, 0);

  Status st = SetOption("no_such_option=3", &o);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(Mentions(st, "unknown")) << st.message();
  EXPECT_TRUE(Mentions(st, "no_such_option")) << st.message();
  EXPECT_TRUE(Mentions(st, "the options are: obb_threshold, ")) << st.message();  // the accepted names follow
  EXPECT_TRUE(Mentions(st, "split_angle_deg")) << st.message();
  EXPECT_TRUE(Mentions(st, "cluster_rule")) << st.message();
  st = SetOption("split_angle_deg", &o);
  EXPECT_FALSE(st.ok());
  EXPECT_TRUE(Mentions(st, "NAME=VALUE")) << st.message();
  for (const char* bad : {"split_angle_deg=abc", "split_angle_deg=", "split_angle_deg=3x", "max_arcs=1.5",
                          "max_arcs=99999999999", "refine_fit=maybe", "backend=cuda", "center_method=foo",
                          "obb_rule=x", "inlier_rule=geometric", "cluster_rule=none", "pair_candidates=2"}) {
    st = SetOption(bad, &o);
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument) << bad;
    EXPECT_TRUE(Mentions(st, "bad value")) << bad << ": " << st.message();
  }
  // A syntactically fine but out-of-range value is ValidateOptions' to refuse.
  EXPECT_TRUE(SetOption("split_angle_deg=95", &o).ok());
  EXPECT_FALSE(ValidateOptions(o).ok());
}

// BUG (runtime/options_parse.cc ParseDouble/ParseInt): a rejected value still overwrites the
// field, e.g. "split_angle_deg=3x" returns "bad value" but leaves split_angle_deg == 3, and
// "max_arcs=1.5" leaves max_arcs == 1. A failed SetOption should leave *options unchanged.
TEST(DetectorErrors, SetOptionLeavesTheFieldAloneOnABadValue) {
  Options o;
  ASSERT_TRUE(SetOption("split_angle_deg=30", &o).ok());
  ASSERT_TRUE(SetOption("max_arcs=12", &o).ok());
  EXPECT_FALSE(SetOption("split_angle_deg=3x", &o).ok());
  EXPECT_EQ(o.split_angle_deg, 30);
  EXPECT_FALSE(SetOption("max_arcs=1.5", &o).ok());
  EXPECT_EQ(o.max_arcs, 12);
}

TEST(DetectorErrors, TinyAndFlatImagesGiveNoEllipses) {
  Detector det;
  DetectionResult r;
  const std::uint8_t one = 7;
  ASSERT_TRUE(det.detect({&one, 1, 1, 1}, &r).ok());
  EXPECT_TRUE(r.ellipses.empty());
  const std::uint8_t six[6] = {0, 255, 0, 255, 0, 255};
  ASSERT_TRUE(det.detect({six, 2, 3, 2}, &r).ok());
  EXPECT_TRUE(r.ellipses.empty());
  ASSERT_TRUE(det.detect({six, 3, 2, 3}, &r).ok());
  EXPECT_TRUE(r.ellipses.empty());
  std::vector<std::uint8_t> flat(320 * 240, 128);
  ASSERT_TRUE(det.detect({flat.data(), 320, 240, 320}, &r).ok());
  EXPECT_TRUE(r.ellipses.empty());
  EXPECT_EQ(r.num_edge_pixels, 0);
}

TEST(DetectorErrors, BackendsReportWhatRan) {
  std::vector<std::uint8_t> img = EllipseImage(200, 160, 200, 0);
  for (Backend b : {Backend::kAuto, Backend::kScalar, Backend::kSimd, Backend::kVulkan}) {
    Options o;
    o.backend = b;
    Detector det(o);
    DetectionResult r;
    r.backend = static_cast<Backend>(99);
    const Status st = det.detect({img.data(), 200, 160, 200}, &r);
    if (!det.status().ok()) {
      EXPECT_EQ(det.status().code(), StatusCode::kUnavailable) << BackendName(b);
      EXPECT_EQ(st.code(), StatusCode::kUnavailable);
      EXPECT_TRUE(Mentions(st, BackendName(b))) << st.message();
      EXPECT_NE(b, Backend::kScalar);
      EXPECT_NE(b, Backend::kAuto);
      continue;
    }
    ASSERT_TRUE(st.ok()) << BackendName(b) << ": " << st.message();
    if (b != Backend::kAuto) EXPECT_EQ(r.backend, b) << BackendName(b);
    EXPECT_NE(r.backend, Backend::kAuto);  // a concrete backend ran
    EXPECT_NE(r.backend, static_cast<Backend>(99));
    EXPECT_EQ(r.ellipses.size(), 1u) << BackendName(b);
  }
}

TEST(DetectorErrors, BackendNamesRoundTrip) {
  for (Backend b : {Backend::kAuto, Backend::kScalar, Backend::kSimd, Backend::kVulkan}) {
    Backend parsed = Backend::kAuto;
    ASSERT_TRUE(ParseBackend(BackendName(b), &parsed)) << BackendName(b);
    EXPECT_EQ(parsed, b);
  }
  Backend x = Backend::kScalar;
  EXPECT_FALSE(ParseBackend("gpu", &x));
  EXPECT_FALSE(ParseBackend("", &x));
}

bool SameEllipses(const DetectionResult& a, const DetectionResult& b) {
  if (a.ellipses.size() != b.ellipses.size()) return false;
  for (std::size_t i = 0; i < a.ellipses.size(); ++i) {
    const Ellipse &x = a.ellipses[i], &y = b.ellipses[i];
    if (x.cx != y.cx || x.cy != y.cy || x.a != y.a || x.b != y.b || x.theta != y.theta || x.score != y.score) return false;
  }
  return a.num_edge_pixels == b.num_edge_pixels && a.num_curves == b.num_curves && a.num_arcs == b.num_arcs &&
         a.num_candidates == b.num_candidates;
}

TEST(DetectorErrors, DeterministicAcrossCallsAndStridePadding) {
  Options o;
  o.backend = Backend::kScalar;
  Detector det(o);
  const int w = 240, h = 180;
  std::vector<std::uint8_t> tight = EllipseImage(w, h, w, 0);
  DetectionResult r1, r2, r3;
  ASSERT_TRUE(det.detect({tight.data(), w, h, w}, &r1).ok());
  ASSERT_EQ(r1.ellipses.size(), 1u);
  EXPECT_NEAR(r1.ellipses[0].cx, w * 0.45, 1.0);
  EXPECT_NEAR(r1.ellipses[0].cy, h * 0.55, 1.0);
  ASSERT_TRUE(det.detect({tight.data(), w, h, w}, &r2).ok());
  EXPECT_TRUE(SameEllipses(r1, r2));
  // A padded copy whose padding bytes are garbage.
  const int stride = w + 37;
  std::vector<std::uint8_t> padded = EllipseImage(w, h, stride, 0);
  std::mt19937 rng(42);
  for (int y = 0; y < h; ++y)
    for (int x = w; x < stride; ++x) padded[static_cast<std::size_t>(y) * stride + x] = static_cast<std::uint8_t>(rng());
  ASSERT_TRUE(det.detect({padded.data(), w, h, stride}, &r3).ok());
  EXPECT_TRUE(SameEllipses(r1, r3));
  // A fresh detector agrees too, and so does one fed frames of another size in between.
  Detector det2(o);
  DetectionResult r4, tmp;
  std::vector<std::uint8_t> other = EllipseImage(100, 90, 100, 0);
  ASSERT_TRUE(det2.detect({other.data(), 100, 90, 100}, &tmp).ok());
  ASSERT_TRUE(det2.detect({tight.data(), w, h, w}, &r4).ok());
  EXPECT_TRUE(SameEllipses(r1, r4));
}

}  // namespace
}  // namespace ellipsekit
