// End to end: Detector with Backend::kSimd finds exactly the ellipses Backend::kScalar finds on
// every dataset image, on every Highway target (DESIGN.md "Backends agree"); plus the backend
// choice, Options::simd_target and ELLIPSEKIT_HWY_TARGET.
#include <gtest/gtest.h>

#include <cctype>
#include <cstdlib>
#include <string>

#include "ellipsekit/detector.h"
#include "ellipsekit/options.h"

#ifdef ELLIPSEKIT_HAVE_SIMD
#include "tests/conformance_util.h"

namespace ellipsekit::conformance {
namespace {

DetectionResult Detect(Backend backend, const std::string& simd_target, const cv::Mat& m) {
  Options options;
  options.backend = backend;
  options.simd_target = simd_target;
  Detector det(options);
  EXPECT_TRUE(det.status().ok()) << det.status().message();
  ImageView view{m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step)};
  DetectionResult r;
  EXPECT_TRUE(det.detect(view, &r).ok());
  return r;
}

std::string Lower(std::string s) {
  for (char& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

TEST(ConformanceDetector, AutoAndSimdResolveToSimd) {
  const KernelTable* table = nullptr;
  std::string why;
  Options options;
  options.backend = Backend::kSimd;
  ASSERT_TRUE(ResolveKernels(options, &table, &why).ok());
  EXPECT_EQ(table->backend, Backend::kSimd);
  options.backend = Backend::kAuto;
  ASSERT_TRUE(ResolveKernels(options, &table, &why).ok());
  EXPECT_EQ(table->backend, Backend::kSimd);
  EXPECT_STREQ(table->simd_target, simd::Targets().front().name);  // the best one
  EXPECT_TRUE(why.empty()) << why;
}

TEST(ConformanceDetector, SimdEqualsScalarOnDatasets) {
  const auto paths = DatasetImagePaths();
  if (paths.empty()) GTEST_SKIP() << "no ../shared/datasets/*/images";
  const auto& targets = simd::Targets();
  int images = 0, ellipses = 0;
  for (const std::string& path : paths) {
    const cv::Mat m = cv::imread(path, cv::IMREAD_GRAYSCALE);
    if (m.empty()) continue;
    ++images;
    const DetectionResult want = Detect(Backend::kScalar, "", m);
    ellipses += static_cast<int>(want.ellipses.size());
    // The best target always; the others on every third image (the back end dominates the time).
    for (std::size_t ti = 0; ti < targets.size(); ++ti) {
      if (ti != 0 && images % 3 != 0) continue;
      const DetectionResult got = Detect(Backend::kSimd, targets[ti].name, m);
      const std::string where = path + " [" + targets[ti].name + "]";
      EXPECT_EQ(got.backend, Backend::kSimd);
      EXPECT_STREQ(got.simd_target, targets[ti].name) << where;
      EXPECT_EQ(got.num_edge_pixels, want.num_edge_pixels) << where;
      EXPECT_EQ(got.num_curves, want.num_curves) << where;
      EXPECT_EQ(got.num_arcs, want.num_arcs) << where;
      ASSERT_EQ(got.ellipses.size(), want.ellipses.size()) << where;
      for (std::size_t i = 0; i < want.ellipses.size(); ++i) {
        // Same stage outputs, same scalar back end: the doubles are equal, not just close.
        EXPECT_EQ(got.ellipses[i].cx, want.ellipses[i].cx) << where;
        EXPECT_EQ(got.ellipses[i].cy, want.ellipses[i].cy) << where;
        EXPECT_EQ(got.ellipses[i].a, want.ellipses[i].a) << where;
        EXPECT_EQ(got.ellipses[i].b, want.ellipses[i].b) << where;
        EXPECT_EQ(got.ellipses[i].theta, want.ellipses[i].theta) << where;
        EXPECT_EQ(got.ellipses[i].score, want.ellipses[i].score) << where;
      }
    }
  }
  std::printf("%d images, %d ellipses, identical on scalar and SIMD\n", images, ellipses);
}

// Options::simd_target picks a target per Detector: two Detectors on two targets side by side,
// each reporting its own, in any letter case; a name that is not available is an error naming the
// available ones, whatever the backend.
TEST(ConformanceDetector, TargetFromOption) {
  const auto& targets = simd::Targets();
  ASSERT_GE(targets.size(), 2u);
  Options first, last;
  first.backend = last.backend = Backend::kSimd;
  first.simd_target = Lower(targets.front().name);
  last.simd_target = targets.back().name;
  Detector a(first), b(last);
  ASSERT_TRUE(a.status().ok()) << a.status().message();
  ASSERT_TRUE(b.status().ok()) << b.status().message();
  const cv::Mat m = cv::Mat(48, 64, CV_8UC1, cv::Scalar(0));
  ImageView view{m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step)};
  DetectionResult ra, rb;
  ASSERT_TRUE(a.detect(view, &ra).ok());
  ASSERT_TRUE(b.detect(view, &rb).ok());
  EXPECT_STREQ(ra.simd_target, targets.front().name);
  EXPECT_STREQ(rb.simd_target, targets.back().name);
  for (Backend backend : {Backend::kAuto, Backend::kSimd, Backend::kScalar}) {
    Options bad;
    bad.backend = backend;
    bad.simd_target = "NO_SUCH_TARGET";
    Detector d(bad);
    EXPECT_EQ(d.status().code(), StatusCode::kInvalidArgument) << BackendName(backend);
    EXPECT_NE(d.status().message().find(targets.back().name), std::string::npos) << d.status().message();
  }
  Options parsed;
  ASSERT_TRUE(SetOption(std::string("simd_target=") + targets.back().name, &parsed).ok());
  EXPECT_EQ(parsed.simd_target, targets.back().name);
}

// ELLIPSEKIT_HWY_TARGET chooses when Options::simd_target is empty (read per Detector); the
// option wins over it. A bad value is an error for kSimd, and kAuto falls back to the best target
// with a note that says why.
TEST(ConformanceDetector, TargetFromEnvironment) {
  const auto& targets = simd::Targets();
  const cv::Mat m = cv::Mat(48, 64, CV_8UC1, cv::Scalar(0));
  ImageView view{m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step)};
  Options simd;
  simd.backend = Backend::kSimd;
  for (const auto& t : targets) {
    ::setenv("ELLIPSEKIT_HWY_TARGET", Lower(t.name).c_str(), 1);
    Detector d(simd);
    DetectionResult r;
    ASSERT_TRUE(d.detect(view, &r).ok()) << d.status().message();
    EXPECT_STREQ(r.simd_target, t.name);
  }
  Options pinned = simd;
  pinned.simd_target = targets.front().name;
  {
    Detector d(pinned);  // the environment names the last target, the option the first
    DetectionResult r;
    ASSERT_TRUE(d.detect(view, &r).ok());
    EXPECT_STREQ(r.simd_target, targets.front().name);
  }
  ::setenv("ELLIPSEKIT_HWY_TARGET", "NO_SUCH_TARGET", 1);
  EXPECT_EQ(Detector(simd).status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(Detector(simd).status().message().find("available"), std::string::npos);
  Options automatic;
  Detector fallback(automatic);
  EXPECT_TRUE(fallback.status().ok());
  EXPECT_NE(fallback.backend_note().find("NO_SUCH_TARGET"), std::string::npos) << fallback.backend_note();
  DetectionResult r;
  ASSERT_TRUE(fallback.detect(view, &r).ok());
  EXPECT_STREQ(r.simd_target, targets.front().name);
  ::unsetenv("ELLIPSEKIT_HWY_TARGET");
  EXPECT_TRUE(Detector(simd).status().ok());
  EXPECT_TRUE(Detector(automatic).backend_note().empty());
}

}  // namespace
}  // namespace ellipsekit::conformance
#else
TEST(ConformanceDetector, SimdNotBuilt) { GTEST_SKIP() << "Highway not found at configure time"; }
#endif
