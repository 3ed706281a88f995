// End to end: Detector with Backend::kSimd finds exactly the ellipses Backend::kScalar finds on
// every dataset image, on every Highway target (DESIGN.md "Backends agree"); plus the backend
// choice and ELLIPSEKIT_HWY_TARGET handling.
#include <gtest/gtest.h>

#include <cstdlib>

#include "ellipsekit/detector.h"

#ifdef ELLIPSEKIT_HAVE_SIMD
#include "tests/conformance_util.h"

namespace ellipsekit::conformance {
namespace {

DetectionResult Detect(Backend backend, const cv::Mat& m) {
  Options options;
  options.backend = backend;
  Detector det(options);
  EXPECT_TRUE(det.status().ok()) << det.status().message();
  ImageView view{m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step)};
  DetectionResult r;
  EXPECT_TRUE(det.detect(view, &r).ok());
  return r;
}

TEST(ConformanceDetector, AutoAndSimdResolveToSimd) {
  const KernelTable* table = nullptr;
  std::string why;
  ASSERT_TRUE(ResolveKernels(Backend::kSimd, &table, &why).ok());
  EXPECT_EQ(table->backend, Backend::kSimd);
  ASSERT_TRUE(ResolveKernels(Backend::kAuto, &table, &why).ok());
  EXPECT_EQ(table->backend, Backend::kSimd);
  EXPECT_TRUE(why.empty()) << why;
}

TEST(ConformanceDetector, SimdEqualsScalarOnDatasets) {
  const auto paths = DatasetImagePaths();
  if (paths.empty()) GTEST_SKIP() << "no ../shared/datasets/*/images";
  TargetReset reset;
  const auto targets = simd::AvailableTargets();
  int images = 0, ellipses = 0;
  for (const std::string& path : paths) {
    const cv::Mat m = cv::imread(path, cv::IMREAD_GRAYSCALE);
    if (m.empty()) continue;
    ++images;
    const DetectionResult want = Detect(Backend::kScalar, m);
    ellipses += static_cast<int>(want.ellipses.size());
    // The best target always; the others on every third image (the back end dominates the time).
    for (std::size_t ti = 0; ti < targets.size(); ++ti) {
      if (ti != 0 && images % 3 != 0) continue;
      simd::ForceTarget(targets[ti]);
      const DetectionResult got = Detect(Backend::kSimd, m);
      const std::string where = path + " [" + simd::TargetName(targets[ti]) + "]";
      EXPECT_EQ(got.backend, Backend::kSimd);
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

TEST(ConformanceDetector, TargetFromEnvironment) {
  TargetReset reset;
  const auto targets = simd::AvailableTargets();
  std::string why;
  for (std::int64_t t : targets) {
    std::string name = simd::TargetName(t);
    for (char& ch : name) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));  // any case
    ::setenv("ELLIPSEKIT_HWY_TARGET", name.c_str(), 1);
    EXPECT_TRUE(simd::ForceTargetFromEnv(&why)) << why;
    EXPECT_EQ(simd::CurrentTarget(), t);
  }
  ::setenv("ELLIPSEKIT_HWY_TARGET", "NO_SUCH_TARGET", 1);
  EXPECT_FALSE(simd::ForceTargetFromEnv(&why));
  EXPECT_NE(why.find("available"), std::string::npos) << why;
  ::unsetenv("ELLIPSEKIT_HWY_TARGET");
  EXPECT_TRUE(simd::ForceTargetFromEnv(&why));
}

}  // namespace
}  // namespace ellipsekit::conformance
#else
TEST(ConformanceDetector, SimdNotBuilt) { GTEST_SKIP() << "Highway not found at configure time"; }
#endif
