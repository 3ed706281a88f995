// When the Vulkan backend's arc stage runs on the CPU (a device without shaderInt64, simulated by
// ELLIPSEKIT_VK_DISABLE_INT64=1), the Detector says so: backend_note() names the reason and
// DetectionResult::arc_backend the CPU backend that ran it, and the ellipses are still scalar's.
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "ellipsekit/detector.h"
#include "tests/ellipse_test_util.h"
#include "tools/scenes/scene_generator.h"

namespace {

using ellipsekit::Backend;

ellipsekit::DetectionResult DetectScene(ellipsekit::Detector* det) {
  const cv::Mat m = ellipsekit::scenes::RenderScene(ellipsekit::scenes::MixSeed(7, 2)).gray;
  ellipsekit::DetectionResult r;
  const ellipsekit::Status st = det->detect({m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step[0])}, &r);
  EXPECT_TRUE(st.ok()) << st.message();
  return r;
}

void ExpectSameEllipses(const ellipsekit::DetectionResult& a, const ellipsekit::DetectionResult& b) {
  EXPECT_TRUE(ellipsekit::test::SameEllipses(a.ellipses, b.ellipses));
}

ellipsekit::Options With(Backend b) {
  ellipsekit::Options o;
  o.backend = b;
  return o;
}

TEST(VulkanFallback, ArcStageOnTheCpuIsReported) {
  ellipsekit::Detector scalar(With(Backend::kScalar));
  const ellipsekit::DetectionResult want = DetectScene(&scalar);
  {
    ellipsekit::Detector device(With(Backend::kVulkan));
    if (!device.status().ok()) GTEST_SKIP() << "no Vulkan device: " << device.status().message();
    const ellipsekit::DetectionResult r = DetectScene(&device);
    EXPECT_EQ(r.backend, Backend::kVulkan);
    if (device.backend_note().empty()) {
      EXPECT_EQ(r.arc_backend, Backend::kVulkan);  // lavapipe has shaderInt64
    } else {
      EXPECT_NE(r.arc_backend, Backend::kVulkan) << device.backend_note();
    }
    ExpectSameEllipses(r, want);
  }
  ASSERT_EQ(setenv("ELLIPSEKIT_VK_DISABLE_INT64", "1", 1), 0);
  ellipsekit::Detector device(With(Backend::kVulkan));
  unsetenv("ELLIPSEKIT_VK_DISABLE_INT64");
  ASSERT_TRUE(device.status().ok()) << device.status().message();
  EXPECT_NE(device.backend_note().find("shaderInt64"), std::string::npos) << device.backend_note();
  EXPECT_NE(device.backend_note().find("arc stage runs on the CPU"), std::string::npos) << device.backend_note();
  const ellipsekit::DetectionResult r = DetectScene(&device);
  EXPECT_EQ(r.backend, Backend::kVulkan);  // the edge stage still ran on the device
  EXPECT_TRUE(r.arc_backend == Backend::kSimd || r.arc_backend == Backend::kScalar)
      << ellipsekit::BackendName(r.arc_backend);
  ExpectSameEllipses(r, want);
}

TEST(VulkanFallback, CpuBackendsRunTheirOwnArcStage) {
  for (const Backend b : {Backend::kScalar, Backend::kSimd, Backend::kAuto}) {
    ellipsekit::Detector det(With(b));
    if (!det.status().ok()) continue;  // a build without SIMD
    const ellipsekit::DetectionResult r = DetectScene(&det);
    EXPECT_EQ(r.arc_backend, r.backend) << ellipsekit::BackendName(b);
  }
}

}  // namespace
