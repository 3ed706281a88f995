// gaussian: every Highway target is bit-identical to the scalar reference (kernels/gaussian.h).
#include <gtest/gtest.h>

#ifdef ELLIPSEKIT_HAVE_SIMD
#include "tests/conformance_util.h"

namespace ellipsekit::conformance {
namespace {

TEST(ConformanceGaussian, OneTablePerTarget) {
  const auto& targets = simd::Targets();
  std::string names;
  for (const auto& t : targets) {
    names += std::string(t.name) + " ";
    // Each table is its own target's, and complete.
    EXPECT_STREQ(t.table.simd_target, t.name);
    EXPECT_EQ(t.table.backend, Backend::kSimd);
    EXPECT_NE(t.arc_split, nullptr);
    EXPECT_NE(t.table.sobel, nullptr);
  }
  std::printf("Highway targets under test: %s\n", names.c_str());
  // At least one vector target next to the scalar fallback on any x86-64 / Arm machine.
  EXPECT_GE(targets.size(), 2u);
}

TEST(ConformanceGaussian, AllImagesAllTargets) {
  for (const ImageCase& c : ConformanceImages()) {
    const int w = c.image.cols, h = c.image.rows;
    const std::ptrdiff_t out_stride = w + c.out_pad;
    ExpectAllTargetsMatchScalar("gaussian " + SizeOf(c), [&](const KernelTable& k) {
      std::vector<Plane> out;
      out.push_back(MakePlane<std::uint8_t>("dst", w, h, out_stride));
      k.gaussian(c.image.data, static_cast<std::ptrdiff_t>(c.image.step), w, h,
                 out[0].data<std::uint8_t>(), out_stride);
      return out;
    });
  }
}

}  // namespace
}  // namespace ellipsekit::conformance
#else
TEST(ConformanceGaussian, SimdNotBuilt) { GTEST_SKIP() << "Highway not found at configure time"; }
#endif
