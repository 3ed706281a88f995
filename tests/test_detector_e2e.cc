// End-to-end: random filled, anti-aliased ellipses on a mildly noisy background, whole and with
// half the rim hidden, must come back with centre, axes and angle close to the drawn ones.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "ellipsekit/ellipsekit.h"
#include "tests/ellipse_test_util.h"
#include "tools/eval/overlap.h"

namespace ellipsekit {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kWidth = 640, kHeight = 480;

struct Scene {
  cv::Mat image;
  std::vector<Ellipse> truth;
};

// Rim point at parameter t.
cv::Point2d RimPoint(const Ellipse& e, double t) {
  const double c = std::cos(e.theta), s = std::sin(e.theta);
  return {e.cx + c * e.a * std::cos(t) - s * e.b * std::sin(t), e.cy + s * e.a * std::cos(t) + c * e.b * std::sin(t)};
}

// Fills `e` with exact anti-aliasing: each pixel (centre at integer coordinates) blends by the
// share of its 4x4 sub-samples inside the ellipse, so the drawn edge is where `e` says it is.
// (cv::ellipse fills a polygon and adds its own AA fringe, a fraction of a pixel off.)
void FillEllipseExact(const Ellipse& e, int gray, cv::Mat* image) {
  const double c = std::cos(e.theta), sn = std::sin(e.theta);
  const int x0 = std::max(0, static_cast<int>(e.cx - e.a) - 2), x1 = std::min(image->cols - 1, static_cast<int>(e.cx + e.a) + 2);
  const int y0 = std::max(0, static_cast<int>(e.cy - e.a) - 2), y1 = std::min(image->rows - 1, static_cast<int>(e.cy + e.a) + 2);
  for (int y = y0; y <= y1; ++y) {
    std::uint8_t* row = image->ptr<std::uint8_t>(y);
    for (int x = x0; x <= x1; ++x) {
      int inside = 0;
      for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 4; ++i) {
          const double dx = x - 0.375 + 0.25 * i - e.cx, dy = y - 0.375 + 0.25 * j - e.cy;
          const double u = (dx * c + dy * sn) / e.a, v = (dy * c - dx * sn) / e.b;
          inside += u * u + v * v <= 1.0;
        }
      }
      row[x] = static_cast<std::uint8_t>(std::lround((row[x] * (16 - inside) + gray * inside) / 16.0));
    }
  }
}

// One scene: 1-3 non-overlapping ellipses. With `occlude`, each gets a background-coloured
// rectangle over half of it, cut along a diameter through the middles of the rim's quadrants I
// and III (so the visible half keeps quadrant II and half of I and III).
Scene MakeScene(std::uint32_t seed, bool occlude) {
  std::mt19937 rng(seed);
  auto uni = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
  Scene s;
  const bool dark_ground = rng() % 2 == 0;
  const int ground = dark_ground ? static_cast<int>(uni(30, 90)) : static_cast<int>(uni(165, 225));
  s.image = cv::Mat(kHeight, kWidth, CV_8UC1, cv::Scalar(ground));
  const int count = 1 + static_cast<int>(rng() % 3);
  for (int attempt = 0; attempt < 200 && static_cast<int>(s.truth.size()) < count; ++attempt) {
    Ellipse e;
    e.a = uni(15, 120);
    e.b = uni(std::max(15.0, 0.35 * e.a), e.a);
    e.theta = uni(-kPi / 2, kPi / 2);
    // Occluders reach up to sqrt(2) (a + 8) from the centre; keep them apart and inside.
    const double reach = occlude ? 1.42 * (e.a + 8) : e.a + 4;
    const double margin = e.a + 6;
    if (2 * margin >= kWidth || 2 * margin >= kHeight) continue;
    e.cx = uni(margin, kWidth - margin);
    e.cy = uni(margin, kHeight - margin);
    bool clear = true;
    for (const Ellipse& o : s.truth) {
      const double other = occlude ? 1.42 * (o.a + 8) : o.a + 4;
      clear &= std::hypot(e.cx - o.cx, e.cy - o.cy) > reach + other + 6;
    }
    if (!clear) continue;
    s.truth.push_back(e);
  }
  for (const Ellipse& e : s.truth) {
    int gray;
    do { gray = static_cast<int>(uni(0, 255)); } while (std::abs(gray - ground) < 70);
    FillEllipseExact(e, gray, &s.image);
  }
  if (occlude) {
    for (const Ellipse& e : s.truth) {
      // Extreme points: rightmost (param tr) and topmost (param tt); the middle of quadrant I is
      // halfway between them on the rim.
      const double c = std::cos(e.theta), sn = std::sin(e.theta);
      const double tr = std::atan2(-e.b * sn, e.a * c);   // maximises x
      const double tt = std::atan2(-e.b * c, -e.a * sn);  // minimises y
      double dt = std::remainder(tt - tr, 2 * kPi);
      const cv::Point2d p1 = RimPoint(e, tr + dt / 2);
      cv::Point2d d(p1.x - e.cx, p1.y - e.cy);
      d /= std::hypot(d.x, d.y);
      cv::Point2d n(-d.y, d.x);
      // Hide the side that holds quadrant IV (the lower-right extreme points).
      const cv::Point2d r = RimPoint(e, tr), b = RimPoint(e, tt + kPi);
      if (n.dot(r - cv::Point2d(e.cx, e.cy)) + n.dot(b - cv::Point2d(e.cx, e.cy)) < 0) n = -n;
      const double L = e.a + 8;
      const cv::Point2d o(e.cx, e.cy);
      const cv::Point2d corners[4] = {o + L * d, o - L * d, o - L * d + L * n, o + L * d + L * n};
      std::vector<cv::Point> poly;
      for (const cv::Point2d& q : corners) poly.emplace_back(static_cast<int>(std::lround(q.x * 16)), static_cast<int>(std::lround(q.y * 16)));
      cv::fillConvexPoly(s.image, poly, cv::Scalar(ground), cv::LINE_AA, 4);
    }
  }
  // Mild noise, sigma 2 gray levels.
  std::normal_distribution<double> noise(0.0, 2.0);
  for (int y = 0; y < kHeight; ++y) {
    std::uint8_t* row = s.image.ptr<std::uint8_t>(y);
    for (int x = 0; x < kWidth; ++x) row[x] = cv::saturate_cast<std::uint8_t>(row[x] + noise(rng));
  }
  return s;
}

double AngleDiffModPi(double x, double y) {
  double d = std::fmod(std::abs(x - y), kPi);
  return std::min(d, kPi - d);
}

bool Matches(const Ellipse& got, const Ellipse& want) {
  if (std::hypot(got.cx - want.cx, got.cy - want.cy) > 1.0) return false;
  if (std::abs(got.a - want.a) > 0.02 * want.a) return false;
  if (std::abs(got.b - want.b) > 0.02 * want.b) return false;
  if (want.a / want.b > 1.1 && AngleDiffModPi(got.theta, want.theta) > 2.0 * kPi / 180) return false;
  return true;
}

// Loose match for false-positive counting: centre within 5 px or a / b within 20 %.
bool Near(const Ellipse& got, const Ellipse& want) {
  return std::hypot(got.cx - want.cx, got.cy - want.cy) < 5 && std::abs(got.a - want.a) < 0.2 * want.a &&
         std::abs(got.b - want.b) < 0.2 * want.b;
}

struct Tally {
  int truth = 0, found = 0, false_positives = 0;
  int found_jaccard = 0;  // detected by the paper's criterion: Jaccard overlap > 0.8
  std::vector<Ellipse> detections;  // for backend comparison
  double min_score = 1, max_score = 0;  // over the detections near a truth ellipse
};

Tally RunScenes(Backend backend, bool occlude, std::uint32_t seed0, int min_truth, double min_edge_coverage = -1) {
  Options o;
  o.backend = backend;
  if (min_edge_coverage >= 0) o.min_edge_coverage = min_edge_coverage;
  Detector det(o);
  EXPECT_TRUE(det.status().ok()) << det.status().message();
  Tally t;
  DetectionResult result;
  for (std::uint32_t seed = seed0; t.truth < min_truth; ++seed) {
    const Scene s = MakeScene(seed, occlude);
    const ImageView view{s.image.data, s.image.cols, s.image.rows, static_cast<std::ptrdiff_t>(s.image.step)};
    const Status st = det.detect(view, &result);
    EXPECT_TRUE(st.ok()) << st.message();
    if (backend == Backend::kScalar) EXPECT_EQ(result.backend, Backend::kScalar);
    for (const Ellipse& want : s.truth) {
      ++t.truth;
      bool ok = false;
      for (const Ellipse& got : result.ellipses) ok |= Matches(got, want);
      t.found += ok;
      bool overlaps = false;
      for (const Ellipse& got : result.ellipses) overlaps |= eval::EllipseJaccard(got, want) > 0.8;
      t.found_jaccard += overlaps;
      if (!ok && std::getenv("ELLIPSEKIT_E2E_VERBOSE")) {
        std::printf("seed %u missed (%.2f %.2f %.2f %.2f %.3f)\n", seed, want.cx, want.cy, want.a, want.b, want.theta);
        for (const Ellipse& got : result.ellipses)
          std::printf("   got (%.2f %.2f %.2f %.2f %.3f)\n", got.cx, got.cy, got.a, got.b, got.theta);
      }
    }
    for (std::size_t i = 0; i < result.ellipses.size(); ++i) {
      const Ellipse& got = result.ellipses[i];
      EXPECT_TRUE(got.score >= 0 && got.score <= 1) << "score " << got.score << " is a share";
      if (i > 0) EXPECT_GE(result.ellipses[i - 1].score, got.score) << "best score first, seed " << seed;
      bool near = false;
      for (const Ellipse& want : s.truth) near |= Near(got, want);
      t.false_positives += !near;
      if (near) {
        t.min_score = std::min(t.min_score, got.score);
        t.max_score = std::max(t.max_score, got.score);
      }
    }
    t.detections.insert(t.detections.end(), result.ellipses.begin(), result.ellipses.end());
  }
  return t;
}

constexpr int kMinTruth = 40;

void Report(const char* what, Backend backend, const Tally& t) {
  std::printf("[ e2e ] %s, backend %s: recovered %d of %d (%.1f %%) within 1 px / 2 %% / 2 deg, "
              "%d with Jaccard > 0.8, false positives %d\n", what, BackendName(backend), t.found, t.truth,
              100.0 * t.found / t.truth, t.found_jaccard, t.false_positives);
  std::printf("[ e2e ] scores of the detections near a truth ellipse: %.3f-%.3f\n", t.min_score, t.max_score);
}

class DetectorE2E : public ::testing::TestWithParam<Backend> {};

TEST_P(DetectorE2E, RecoversWholeEllipses) {
  const Tally t = RunScenes(GetParam(), /*occlude=*/false, 1000, kMinTruth);
  Report("whole ellipses", GetParam(), t);
  ASSERT_GE(t.truth, kMinTruth);
  // Measured (seeds 1000.., 40 ellipses, both backends): 40 of 40 within 1 px / 2 % / 2 deg.
  EXPECT_GE(t.found, t.truth * 90 / 100);
  EXPECT_LE(t.false_positives, 2);
  // The score is the share of the outline that edges back (measured 1.000 on all 40).
  EXPECT_GE(t.min_score, 0.95);
}

TEST_P(DetectorE2E, RecoversHalfOccludedEllipses) {
  // Half an outline is below the default edge coverage (Options::min_edge_coverage 0.7, which the
  // generated scenes and the real datasets favour; with it none of these 40 is reported): a
  // caller expecting heavy occlusion lowers it, as here.
  const Tally t = RunScenes(GetParam(), /*occlude=*/true, 5000, kMinTruth, /*min_edge_coverage=*/0.4);
  Report("half-occluded ellipses", GetParam(), t);
  ASSERT_GE(t.truth, kMinTruth);
  // Half the rim leaves one full quadrant and two half quadrants, so the arc triplet is short and
  // the fit less exact: measured (seeds 5000.., 40 ellipses, min_edge_coverage 0.4) 17 of 40 within
  // 1 px / 2 % / 2 deg, 22 of 40 with Jaccard > 0.8 (the detector needs arcs from three quadrants),
  // 0 false positives, both backends. Floors: the measured counts less two (a tenth), so losing a
  // few of these fails here.
  EXPECT_GE(t.found_jaccard, 20);
  EXPECT_GE(t.found, 15);
  // The occluders' straight edges must not produce ellipses of their own (measured 0).
  EXPECT_LE(t.false_positives, 1);
  // Half the outline is hidden, and the score says so (measured 0.484-0.516).
  EXPECT_GE(t.min_score, 0.4);
  EXPECT_LE(t.max_score, 0.6);
}

INSTANTIATE_TEST_SUITE_P(Backends, DetectorE2E, ::testing::Values(Backend::kScalar, Backend::kAuto),
                         [](const ::testing::TestParamInfo<Backend>& info) {
                           return std::string(BackendName(info.param));
                         });

TEST(DetectorE2EBackends, AutoAndScalarGiveIdenticalEllipses) {
  const Tally a = RunScenes(Backend::kScalar, false, 1000, 12);
  const Tally b = RunScenes(Backend::kAuto, false, 1000, 12);
  EXPECT_TRUE(test::SameEllipses(a.detections, b.detections));
}

}  // namespace
}  // namespace ellipsekit
