// canny_thresholds: the SIMD backend's magnitude histogram and tiles' maxima equal the scalar
// reference's (kernels/canny_thresholds.h), so the thresholds agree too.
#include <gtest/gtest.h>

#ifdef ELLIPSEKIT_HAVE_SIMD
#include "kernels/canny_thresholds.h"
#include "tests/conformance_util.h"

namespace ellipsekit::conformance {
namespace {

void CheckHistogram(const std::string& what, const Gradients& g) {
  // 32 / 64 px tiles (a frame's edge cuts the last ones), and one tile.
  for (int shift : {kNmsMinTileShift, kNmsMinTileShift + 1, kNmsOneTileShift}) {
    const int tiles = TilesAlong(g.width, shift) * TilesAlong(g.height, shift);
    ExpectAllTargetsMatchScalar("magnitude_histogram " + what + " tile shift " + std::to_string(shift),
                                [&](const KernelTable& k) {
                                  std::vector<Plane> out;
                                  out.push_back(MakePlane<std::uint32_t>("hist", kMaxMagnitude + 1, 1, kMaxMagnitude + 1));
                                  out.push_back(MakePlane<std::uint16_t>("tile_max", tiles, 1, tiles));
                                  k.magnitude_histogram(g.mag.data(), g.width, g.height, g.stride, shift,
                                                        out[0].data<std::uint32_t>(), out[1].data<std::uint16_t>());
                                  return out;
                                });
  }
}

TEST(ConformanceCannyThresholds, AllImagesAllTargets) {
  for (const ImageCase& c : ConformanceImages()) CheckHistogram(SizeOf(c), GradientsOf(c));
}

TEST(ConformanceCannyThresholds, FullMagnitudeRange) {
  std::uint32_t seed = 100;
  for (auto [w, h] : {std::pair{1, 1}, {3, 2}, {5, 7}, {67, 5}, {640, 480}}) {
    CheckHistogram("random gradients " + std::to_string(w) + "x" + std::to_string(h),
                   RandomGradients(w, h, w + 3, 1020, seed++));
  }
}

}  // namespace
}  // namespace ellipsekit::conformance
#else
TEST(ConformanceCannyThresholds, SimdNotBuilt) { GTEST_SKIP() << "Highway not found at configure time"; }
#endif
