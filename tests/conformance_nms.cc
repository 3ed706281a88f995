// nms: every Highway target is bit-identical to the scalar reference (kernels/nms.h).
#include <gtest/gtest.h>

#ifdef ELLIPSEKIT_HAVE_SIMD
#include "kernels/canny_thresholds.h"
#include "tests/conformance_util.h"

namespace ellipsekit::conformance {
namespace {

void CheckNms(const std::string& what, const Gradients& g, int low, int high, int out_pad) {
  const std::ptrdiff_t out_stride = g.width + out_pad;
  ExpectAllTargetsMatchScalar("nms " + what + " low=" + std::to_string(low) + " high=" + std::to_string(high),
                              [&](const KernelTable& k) {
                                std::vector<Plane> out;
                                out.push_back(MakePlane<std::uint8_t>("out", g.width, g.height, out_stride));
                                k.nms(g.dx.data(), g.dy.data(), g.mag.data(), g.width, g.height, g.stride,
                                      low, high, out[0].data<std::uint8_t>(), out_stride);
                                return out;
                              });
}

TEST(ConformanceNms, AllImagesAllTargets) {
  std::vector<std::uint32_t> hist(kMaxMagnitude + 1);
  for (const ImageCase& c : ConformanceImages()) {
    const Gradients g = GradientsOf(c);
    ScalarKernels().magnitude_histogram(g.mag.data(), g.width, g.height, g.stride, hist.data());
    const CannyThresholds th = ThresholdsFromHistogram(hist.data(), 900, 400, 8, 0);
    CheckNms(SizeOf(c), g, th.low, th.high, c.out_pad);
    CheckNms(SizeOf(c), g, 0, 0, c.out_pad);  // every local maximum counts
  }
}

// Gradients with no image behind them: all directions, exact direction-boundary ratios, zero
// components, and (range 3) many equal neighbours, where > and >= differ.
TEST(ConformanceNms, RandomGradients) {
  std::uint32_t seed = 200;
  for (int range : {1, 3, 40, 1020}) {
    for (auto [w, h] : {std::pair{1, 1}, {2, 3}, {3, 3}, {7, 5}, {70, 4}, {129, 9}, {640, 480}}) {
      const Gradients g = RandomGradients(w, h, w + 5, range, seed++);
      const std::string what = "random range=" + std::to_string(range) + " " + std::to_string(w) + "x" + std::to_string(h);
      CheckNms(what, g, 0, range, 3);
      CheckNms(what, g, range / 2, range, 0);
    }
  }
  for (int w = 1; w <= 70; ++w) CheckNms("random w=" + std::to_string(w), RandomGradients(w, 4, w, 3, seed++), 0, 2, 1);
}

}  // namespace
}  // namespace ellipsekit::conformance
#else
TEST(ConformanceNms, SimdNotBuilt) { GTEST_SKIP() << "Highway not found at configure time"; }
#endif
