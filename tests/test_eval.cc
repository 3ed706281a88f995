// Tests of tools/eval: the Jaccard overlap of ellipses, matching rules (sec. III-A), P/R/F
// arithmetic, the ground-truth format and dataset listing.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "tools/eval/dataset.h"
#include "tools/eval/ellipse_io.h"
#include "tools/eval/metrics.h"
#include "tools/eval/overlap.h"

namespace ellipsekit::eval {
namespace {

constexpr double kPi = std::numbers::pi;

Ellipse E(double cx, double cy, double a, double b, double theta = 0) {
  Ellipse e;
  e.cx = cx;
  e.cy = cy;
  e.a = a;
  e.b = b;
  e.theta = theta;
  return e;
}

bool InsideEllipse(const Ellipse& e, double x, double y) {
  const double c = std::cos(e.theta), s = std::sin(e.theta);
  const double dx = x - e.cx, dy = y - e.cy;
  const double u = (c * dx + s * dy) / e.a, v = (-s * dx + c * dy) / e.b;
  return u * u + v * v <= 1;
}

// Jaccard by counting the centres of a fine grid of cells inside both / either ellipse.
double BruteForceJaccard(const Ellipse& p, const Ellipse& q, double step) {
  const BoundingBox bp = EllipseBounds(p), bq = EllipseBounds(q);
  const double x0 = std::min(bp.x0, bq.x0), x1 = std::max(bp.x1, bq.x1);
  const double y0 = std::min(bp.y0, bq.y0), y1 = std::max(bp.y1, bq.y1);
  long inter = 0, uni = 0;
  for (double y = y0 + step / 2; y < y1; y += step) {
    for (double x = x0 + step / 2; x < x1; x += step) {
      const bool in_p = InsideEllipse(p, x, y), in_q = InsideEllipse(q, x, y);
      inter += in_p && in_q;
      uni += in_p || in_q;
    }
  }
  return static_cast<double>(inter) / static_cast<double>(uni);
}

// ---------------------------------------------------------------- overlap

TEST(EllipseJaccard, IdenticalIsOne) {
  for (const Ellipse& e : {E(0, 0, 1, 1), E(100.5, 40.25, 60, 20, 0.3), E(-5, 7, 3, 2.9, -1.5),
                           E(320, 240, 200, 3, 1.2)}) {
    EXPECT_NEAR(EllipseJaccard(e, e), 1.0, 1e-5);
  }
}

TEST(EllipseJaccard, ConcentricCircles) {
  for (double r1 : {1.0, 5.0, 9.0, 30.0}) {
    const double r2 = 40.0;
    const double expected = (r1 * r1) / (r2 * r2);
    EXPECT_NEAR(EllipseJaccard(E(10, 20, r1, r1), E(10, 20, r2, r2)), expected, 1e-5) << r1;
    EXPECT_NEAR(EllipseJaccard(E(10, 20, r2, r2), E(10, 20, r1, r1)), expected, 1e-5) << r1;
  }
}

TEST(EllipseJaccard, ConcentricScaledEllipses) {
  const Ellipse big = E(50, 60, 30, 12, 0.7);
  const Ellipse small = E(50, 60, 24, 9.6, 0.7);  // scale 0.8 -> area ratio 0.64
  EXPECT_NEAR(EllipseJaccard(big, small), 0.64, 1e-5);
}

TEST(EllipseJaccard, DisjointIsZero) {
  EXPECT_EQ(EllipseJaccard(E(0, 0, 10, 5), E(100, 100, 10, 5)), 0.0);
  // Bounding boxes overlap (diagonal neighbours) but the discs do not touch.
  const double d = 2 * 10 / std::sqrt(2.0) + 0.5;
  EXPECT_NEAR(EllipseJaccard(E(0, 0, 10, 10), E(d, d, 10, 10)), 0.0, 1e-12);
}

TEST(EllipseJaccard, TwoCirclesLens) {
  // Two unit-radius-r discs at distance d: lens area 2 r^2 acos(d/2r) - (d/2) sqrt(4r^2 - d^2).
  const double r = 20, d = 13;
  const double lens = 2 * r * r * std::acos(d / (2 * r)) - d / 2 * std::sqrt(4 * r * r - d * d);
  const double expected = lens / (2 * kPi * r * r - lens);
  EXPECT_NEAR(EllipseJaccard(E(5, 5, r, r), E(5 + d, 5, r, r)), expected, 1e-5);
  EXPECT_NEAR(EllipseIntersectionArea(E(5, 5, r, r), E(5 + d, 5, r, r)), lens, 1e-3);
}

TEST(EllipseJaccard, RotatedByNinetyDegrees) {
  const Ellipse p = E(30.3, -12.7, 40, 20, 0.25);
  Ellipse q = p;
  q.theta += kPi / 2;
  const double brute = BruteForceJaccard(p, q, 0.05);
  // Closed form for the intersection of x^2/a^2 + y^2/b^2 <= 1 and its 90-degree rotation.
  const double inter = 4 * p.a * p.b * std::atan(p.b / p.a);
  const double analytic = inter / (2 * kPi * p.a * p.b - inter);
  EXPECT_NEAR(brute, analytic, 1e-3);  // the brute force itself is good to ~1e-4
  EXPECT_NEAR(EllipseJaccard(p, q), analytic, 1e-5);
  EXPECT_NEAR(EllipseJaccard(p, q), brute, 1e-3);
}

TEST(EllipseJaccard, GeneralPairAgainstBruteForceAndSymmetric) {
  const Ellipse p = E(10, 10, 25, 9, 0.4), q = E(18, 14, 19, 14, -0.9);
  const double j = EllipseJaccard(p, q);
  EXPECT_NEAR(j, BruteForceJaccard(p, q, 0.03), 1e-3);
  EXPECT_NEAR(j, EllipseJaccard(q, p), 1e-6);
}

TEST(EllipseJaccard, DegenerateIsZero) {
  EXPECT_EQ(EllipseJaccard(E(0, 0, 0, 0), E(0, 0, 1, 1)), 0.0);
  EXPECT_EQ(EllipseJaccard(E(0, 0, 1, -1), E(0, 0, 1, 1)), 0.0);
  EXPECT_EQ(EllipseJaccard(E(NAN, 0, 1, 1), E(0, 0, 1, 1)), 0.0);
}

// ---------------------------------------------------------------- matching

TEST(MatchEllipses, EachTruthMatchedOnce) {
  const std::vector<Ellipse> truth = {E(100, 100, 30, 20, 0.1)};
  const std::vector<Ellipse> dets = {E(100, 100, 30, 20, 0.1), E(100.5, 100, 30, 20, 0.1)};
  const MatchResult r = MatchEllipses(dets, truth);
  EXPECT_EQ(r.counts, (MatchCounts{2, 1, 1}));
  ASSERT_EQ(r.pairs.size(), 1u);
  EXPECT_EQ(r.pairs[0].detection, 0);  // the exact one has the higher overlap
  EXPECT_EQ(r.truth_of_detection[1], -1);
}

TEST(MatchEllipses, EachDetectionMatchedOnce) {
  const std::vector<Ellipse> truth = {E(100, 100, 30, 20, 0.1), E(100.4, 100, 30, 20, 0.1)};
  const std::vector<Ellipse> dets = {E(100.2, 100, 30, 20, 0.1)};
  const MatchResult r = MatchEllipses(dets, truth);
  EXPECT_EQ(r.counts, (MatchCounts{1, 2, 1}));
}

TEST(MatchEllipses, ThresholdIsStrict) {
  const Ellipse g = E(0, 0, 10, 10);
  const Ellipse d = E(0, 0, 9, 9);  // Phi = 0.81
  EXPECT_EQ(MatchEllipses({d}, {g}).counts.correct, 1);
  EXPECT_EQ(MatchEllipses({E(0, 0, std::sqrt(79.0), std::sqrt(79.0))}, {g}).counts.correct, 0);
  const double phi = EllipseJaccard(d, g);
  EXPECT_EQ(MatchEllipses({d}, {g}, phi).counts.correct, 0);  // Phi > threshold, not >=
  EXPECT_EQ(MatchEllipses({d}, {g}, phi - 1e-9).counts.correct, 1);
  EXPECT_EQ(kOverlapThreshold, 0.8);
}

TEST(MatchEllipses, MaximumCardinalityBeatsGreedy) {
  // Concentric circles, Phi = (r_small / r_big)^2:
  //   D0 (9.75) ~ T0 (10): 0.951, D0 ~ T1 (9.3): 0.910, D1 (10.5) ~ T0: 0.907, D1 ~ T1: 0.784.
  // Greedy takes D0-T0 and stops at 1; the maximum pairs D0-T1 and D1-T0.
  const std::vector<Ellipse> truth = {E(0, 0, 10, 10), E(0, 0, 9.3, 9.3)};
  const std::vector<Ellipse> dets = {E(0, 0, 9.75, 9.75), E(0, 0, 10.5, 10.5)};
  const MatchResult r = MatchEllipses(dets, truth);
  EXPECT_EQ(r.counts, (MatchCounts{2, 2, 2}));
  EXPECT_EQ(r.truth_of_detection, (std::vector<int>{1, 0}));
  EXPECT_EQ(r.detection_of_truth, (std::vector<int>{1, 0}));
}

TEST(MatchEllipses, EmptyInputs) {
  EXPECT_EQ(MatchEllipses({}, {}).counts, (MatchCounts{0, 0, 0}));
  EXPECT_EQ(MatchEllipses({E(0, 0, 5, 5)}, {}).counts, (MatchCounts{1, 0, 0}));
  EXPECT_EQ(MatchEllipses({}, {E(0, 0, 5, 5)}).counts, (MatchCounts{0, 1, 0}));
}

TEST(MatchEllipses, DontCareBoxes) {
  const std::vector<Ellipse> truth = {E(10, 10, 8, 8), E(100, 100, 20, 20)};
  const std::vector<Ellipse> dets = {E(10, 10, 5, 5), E(100, 100, 20, 20), E(12, 9, 7, 7)};
  const std::vector<BoundingBox> boxes = {{0, 0, 20, 20}};
  const MatchResult r = MatchEllipses(dets, truth, kOverlapThreshold, boxes);
  // Truth 0 and the two detections near it are don't-care; truth 1 is found.
  EXPECT_EQ(r.counts, (MatchCounts{1, 1, 1}));
  EXPECT_TRUE(r.truth_ignored[0]);
  EXPECT_TRUE(r.detection_ignored[0]);
  EXPECT_TRUE(r.detection_ignored[2]);
}

TEST(Metrics, PrecisionRecallF) {
  const MatchCounts c{10, 8, 6};
  EXPECT_DOUBLE_EQ(Precision(c), 0.6);
  EXPECT_DOUBLE_EQ(Recall(c), 0.75);
  EXPECT_NEAR(FMeasure(c), 2 * 0.6 * 0.75 / 1.35, 1e-15);
  EXPECT_DOUBLE_EQ(FMeasure(1.0, 1.0), 1.0);
}

TEST(Metrics, CountsSumOverImages) {
  MatchCounts total;
  total += MatchCounts{3, 2, 2};
  total += MatchCounts{1, 4, 1};
  EXPECT_EQ(total, (MatchCounts{4, 6, 3}));
  EXPECT_EQ(MatchCounts({1, 1, 1}) + MatchCounts({2, 2, 0}), (MatchCounts{3, 3, 1}));
  // Micro average: ratios of the sums, not the mean of per-image ratios.
  EXPECT_DOUBLE_EQ(Precision(total), 0.75);
  EXPECT_DOUBLE_EQ(Recall(total), 0.5);
}

TEST(Metrics, EmptyCases) {
  EXPECT_EQ(Precision({0, 5, 0}), 1.0);  // nothing detected: no false claim
  EXPECT_EQ(Recall({0, 5, 0}), 0.0);
  EXPECT_EQ(FMeasure(MatchCounts{0, 5, 0}), 0.0);
  EXPECT_EQ(Recall({3, 0, 0}), 1.0);  // no ground truth: nothing missed
  EXPECT_EQ(Precision({3, 0, 0}), 0.0);
  EXPECT_EQ(FMeasure(MatchCounts{3, 0, 0}), 0.0);
  EXPECT_EQ(FMeasure(MatchCounts{0, 0, 0}), 1.0);
  EXPECT_EQ(FMeasure(0.0, 0.0), 0.0);
}

// ---------------------------------------------------------------- ground truth format

TEST(ParseEllipses, ReadsLinesCommentsAndBlanks) {
  std::vector<Ellipse> out;
  const std::string text =
      "# header\n"
      "\n"
      "10 20 30 15 0.5\n"
      "   \t\n"
      "1.5e1 -2 4 4 0   # trailing comment\r\n"
      "7 8 3 5 0.25";  // a < b: swapped, theta + pi/2; no final newline
  ASSERT_TRUE(ParseEllipses(text, "t.txt", &out).ok());
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].cx, 10);
  EXPECT_EQ(out[0].cy, 20);
  EXPECT_EQ(out[0].a, 30);
  EXPECT_EQ(out[0].b, 15);
  EXPECT_EQ(out[0].theta, 0.5);
  EXPECT_EQ(out[1].cx, 15);
  EXPECT_EQ(out[1].cy, -2);
  EXPECT_EQ(out[2].a, 5);
  EXPECT_EQ(out[2].b, 3);
  EXPECT_NEAR(out[2].theta, 0.25 + kPi / 2 - kPi, 1e-12);  // normalised to [-pi/2, pi/2)
}

TEST(ParseEllipses, ErrorsNameFileAndLine) {
  std::vector<Ellipse> out;
  struct Case {
    const char* text;
    const char* needle;
  };
  for (const Case& c : {Case{"1 2 3 4 0\n\n1 2 3 4\n", "gt/x.txt:3:"},
                        Case{"1 2 3 4 0 9\n", "gt/x.txt:1:"},
                        Case{"# c\n1 2 abc 4 0\n", "gt/x.txt:2: not a number: 'abc'"},
                        Case{"1 2 3x 4 0\n", "gt/x.txt:1:"},
                        Case{"1 2 -3 4 0\n", "gt/x.txt:1: semi-axes"},
                        Case{"1 2 3 0 0\n", "gt/x.txt:1: semi-axes"},
                        Case{"1 2 inf 4 0\n", "gt/x.txt:1:"}}) {
    const Status st = ParseEllipses(c.text, "gt/x.txt", &out);
    EXPECT_FALSE(st.ok()) << c.text;
    EXPECT_NE(st.message().find(c.needle), std::string::npos) << st.message();
  }
}

TEST(ParseEllipses, MissingFileIsNamed) {
  std::vector<Ellipse> out;
  const Status st = ReadEllipses("/nonexistent/dir/gt.txt", &out);
  EXPECT_FALSE(st.ok());
  EXPECT_NE(st.message().find("/nonexistent/dir/gt.txt"), std::string::npos);
}

TEST(NormalizeAngle, Range) {
  for (double t : {-10.0, -kPi / 2, -1.0, 0.0, 1.0, kPi / 2, 3.0, 10.0}) {
    const double n = NormalizeAngle(t);
    EXPECT_GE(n, -kPi / 2);
    EXPECT_LT(n, kPi / 2);
    EXPECT_NEAR(std::remainder(n - t, kPi), 0.0, 1e-12);
  }
}

class TempDir {
 public:
  TempDir() {
    path_ = std::filesystem::temp_directory_path() /
            ("ellipsekit_test_eval_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
             "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

void Touch(const std::filesystem::path& p, const std::string& text = "") {
  std::filesystem::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

TEST(WriteEllipses, RoundTrip) {
  TempDir dir;
  const std::vector<Ellipse> in = {E(1.25, 2.5, 30, 10, 0.125), E(100, 200, 5, 5, -1.5)};
  const std::string path = (dir.path() / "out.txt").string();
  ASSERT_TRUE(WriteEllipses(path, in).ok());
  std::vector<Ellipse> out;
  ASSERT_TRUE(ReadEllipses(path, &out).ok());
  ASSERT_EQ(out.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(out[i].cx, in[i].cx, 1e-4);
    EXPECT_NEAR(out[i].cy, in[i].cy, 1e-4);
    EXPECT_NEAR(out[i].a, in[i].a, 1e-4);
    EXPECT_NEAR(out[i].b, in[i].b, 1e-4);
    EXPECT_NEAR(out[i].theta, in[i].theta, 1e-6);
  }
  // No temporary file is left behind.
  int files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 1);
}

// ---------------------------------------------------------------- datasets

TEST(LoadDataset, SharedSmartphoneSubset) {
  Dataset ds;
  const std::string dir = std::string(ELLIPSEKIT_SOURCE_DIR) + "/../shared/datasets/smartphone_subset";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << "no shared datasets at " << dir;
  const Status st = LoadDataset(dir, &ds);
  ASSERT_TRUE(st.ok()) << st.message();
  ASSERT_EQ(ds.images.size(), 2u);
  EXPECT_EQ(ds.images[0].stem, "04_00010");
  EXPECT_EQ(ds.images[1].stem, "09_00006");
  int total = 0;
  for (const DatasetImage& image : ds.images) {
    std::vector<Ellipse> truth;
    ASSERT_TRUE(ReadEllipses(image.truth_path, &truth).ok());
    total += static_cast<int>(truth.size());
  }
  EXPECT_EQ(total, 3);
}

TEST(LoadDataset, SharedDatasetsAllParse) {
  const std::string root = std::string(ELLIPSEKIT_SOURCE_DIR) + "/../shared/datasets";
  if (!std::filesystem::exists(root)) GTEST_SKIP() << "no shared datasets at " << root;
  for (const char* name : {"prasad_subset", "smartphone_subset", "su2019_coin", "edcircles_mini"}) {
    Dataset ds;
    const Status st = LoadDataset(root + "/" + name, &ds);
    ASSERT_TRUE(st.ok()) << st.message();
    for (const DatasetImage& image : ds.images) {
      std::vector<Ellipse> truth;
      const Status read = ReadEllipses(image.truth_path, &truth);
      EXPECT_TRUE(read.ok()) << read.message();
    }
  }
}

TEST(LoadDataset, SortedAndErrors) {
  TempDir dir;
  const auto root = dir.path();
  Dataset ds;
  Status st = LoadDataset(root.string(), &ds);
  EXPECT_FALSE(st.ok());
  EXPECT_NE(st.message().find("images"), std::string::npos) << st.message();

  Touch(root / "images" / "b.png");
  Touch(root / "images" / "a.JPG");
  Touch(root / "images" / "notes.txt");
  Touch(root / "gt" / "a.txt", "1 2 3 2 0\n");
  st = LoadDataset(root.string(), &ds);
  EXPECT_FALSE(st.ok());
  EXPECT_NE(st.message().find("b.png"), std::string::npos) << st.message();
  EXPECT_NE(st.message().find("gt/b.txt"), std::string::npos) << st.message();

  Touch(root / "gt" / "b.txt");
  st = LoadDataset(root.string(), &ds);
  ASSERT_TRUE(st.ok()) << st.message();
  ASSERT_EQ(ds.images.size(), 2u);
  EXPECT_EQ(ds.images[0].stem, "a");
  EXPECT_EQ(ds.images[1].stem, "b");
  EXPECT_TRUE(ds.dont_care.empty());

  Touch(root / "border_boxes.txt", "# stem x0 y0 x1 y1\nb 0 0 10 20\n\n");
  st = LoadDataset(root.string(), &ds);
  ASSERT_TRUE(st.ok()) << st.message();
  ASSERT_EQ(ds.dont_care.count("b"), 1u);
  EXPECT_EQ(ds.dont_care["b"][0].y1, 20);

  Touch(root / "border_boxes.txt", "b 0 0 10\n");
  st = LoadDataset(root.string(), &ds);
  EXPECT_FALSE(st.ok());
  EXPECT_NE(st.message().find("border_boxes.txt:1"), std::string::npos) << st.message();

  EXPECT_FALSE(LoadDataset((root / "missing").string(), &ds).ok());
}

}  // namespace
}  // namespace ellipsekit::eval
