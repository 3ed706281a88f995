// hysteresis: every Highway target is bit-identical to the scalar reference (kernels/hysteresis.h).
#include <gtest/gtest.h>

#ifdef ELLIPSEKIT_HAVE_SIMD
#include "kernels/canny_thresholds.h"
#include "kernels/nms.h"
#include "tests/conformance_util.h"

namespace ellipsekit::conformance {
namespace {

// Runs hysteresis in place on a copy of `nms` (width x height, rows `stride` bytes apart; the
// padding keeps kSentinel, so a write outside the region is caught).
void CheckHysteresis(const std::string& what, const std::vector<std::uint8_t>& nms, int width,
                     int height, std::ptrdiff_t stride) {
  ExpectAllTargetsMatchScalar("hysteresis " + what, [&](const KernelTable& k) {
    std::vector<Plane> out;
    out.push_back(MakePlane<std::uint8_t>("map", width, height, stride));
    std::uint8_t* map = out[0].data<std::uint8_t>();
    for (int y = 0; y < height; ++y) {
      std::copy_n(nms.data() + y * stride, width, map + y * stride);
    }
    std::vector<std::int32_t> stack(static_cast<std::size_t>(width) * height);
    k.hysteresis(map, width, height, stride, stack.data());
    return out;
  });
}

// NMS maps of real and synthetic images (the input hysteresis sees in detect()).
TEST(ConformanceHysteresis, AllImagesAllTargets) {
  for (const ImageCase& c : ConformanceImages()) {
    const Gradients g = GradientsOf(c);
    const CannyTiles tiles = TilesOf(g);
    std::vector<std::uint8_t> nms(static_cast<std::size_t>(g.stride) * g.height, kSentinel);
    ScalarKernels().nms(g.dx.data(), g.dy.data(), g.mag.data(), g.width, g.height, g.stride, tiles.view(),
                        nms.data(), g.stride);
    CheckHysteresis(SizeOf(c), nms, g.width, g.height, g.stride);
  }
}

// Maps of 0 / 1 / 2 with no image behind them: strong pixels anywhere (first and last column,
// every lane of a vector, several in one vector whose floods reach each other), weak components
// that touch a strong one only diagonally, and densities from sparse to nearly full.
TEST(ConformanceHysteresis, RandomMaps) {
  std::mt19937 rng(11);
  for (int permille_weak : {30, 300, 700}) {
    for (int permille_strong : {1, 20, 200}) {
      for (auto [w, h] : {std::pair{1, 1}, {2, 3}, {7, 5}, {63, 4}, {64, 4}, {65, 9}, {129, 17}, {640, 480}}) {
        const std::ptrdiff_t stride = w + 3;
        std::vector<std::uint8_t> nms(static_cast<std::size_t>(stride) * h, kSentinel);
        std::uniform_int_distribution<int> u(0, 999);
        for (int y = 0; y < h; ++y) {
          for (int x = 0; x < w; ++x) {
            const int r = u(rng);
            nms[y * stride + x] = r < permille_strong ? kNmsStrong : r < permille_strong + permille_weak ? kNmsWeak : kNmsNone;
          }
        }
        CheckHysteresis("random weak=" + std::to_string(permille_weak) + " strong=" + std::to_string(permille_strong) +
                            " " + std::to_string(w) + "x" + std::to_string(h),
                        nms, w, h, stride);
      }
    }
  }
}

// One weak serpentine, strong only at its far end: the flood must walk the whole frame back.
TEST(ConformanceHysteresis, SerpentineFromItsFarEnd) {
  const int w = 200, h = 97;
  std::vector<std::uint8_t> nms(static_cast<std::size_t>(w) * h, kNmsNone);
  for (int y = 0; y < h; y += 2) {
    for (int x = 0; x < w; ++x) nms[y * w + x] = kNmsWeak;
    if (y + 1 < h) nms[(y + 1) * w + ((y / 2) % 2 == 0 ? w - 1 : 0)] = kNmsWeak;
  }
  nms[(h - 1) * w + w / 2] = kNmsStrong;
  CheckHysteresis("serpentine", nms, w, h, w);
}

}  // namespace
}  // namespace ellipsekit::conformance
#else
TEST(ConformanceHysteresis, SimdNotBuilt) { GTEST_SKIP() << "Highway not found at configure time"; }
#endif
