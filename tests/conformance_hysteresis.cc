// hysteresis: every Highway target is bit-identical to the scalar reference (kernels/hysteresis.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

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

// The contract itself, with no flood: "weak or strong with an edge neighbour becomes an edge",
// repeated until nothing changes, from the strong pixels. The scalar reference must equal it (the
// CPU tables share its flood, so matching each other alone would not catch a flood that stops
// short).
std::vector<std::uint8_t> HysteresisByDefinition(const std::vector<std::uint8_t>& nms, int width, int height,
                                                 std::ptrdiff_t stride) {
  std::vector<std::uint8_t> edge(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) edge[y * width + x] = nms[y * stride + x] == kNmsStrong;
  }
  for (bool changed = true; changed;) {
    changed = false;
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        if (edge[y * width + x] || nms[y * stride + x] != kNmsWeak) continue;
        for (int ny = std::max(y - 1, 0); ny <= std::min(y + 1, height - 1) && !edge[y * width + x]; ++ny) {
          for (int nx = std::max(x - 1, 0); nx <= std::min(x + 1, width - 1); ++nx) {
            if (edge[ny * width + nx]) {
              edge[y * width + x] = 1;
              changed = true;
              break;
            }
          }
        }
      }
    }
  }
  return edge;
}

void CheckScalarMatchesDefinition(const std::string& what, const std::vector<std::uint8_t>& nms, int width,
                                  int height, std::ptrdiff_t stride) {
  std::vector<std::uint8_t> map = nms;
  std::vector<std::int32_t> stack(static_cast<std::size_t>(width) * height);
  ScalarKernels().hysteresis(map.data(), width, height, stride, stack.data());
  const std::vector<std::uint8_t> expected = HysteresisByDefinition(nms, width, height, stride);
  int wrong = 0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) wrong += map[y * stride + x] != expected[y * width + x];
  }
  EXPECT_EQ(wrong, 0) << what;
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
        const std::string what = "random weak=" + std::to_string(permille_weak) +
                                 " strong=" + std::to_string(permille_strong) + " " + std::to_string(w) + "x" +
                                 std::to_string(h);
        CheckHysteresis(what, nms, w, h, stride);
        CheckScalarMatchesDefinition(what, nms, w, h, stride);
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
  CheckScalarMatchesDefinition("serpentine", nms, w, h, w);
}

}  // namespace
}  // namespace ellipsekit::conformance
#else
TEST(ConformanceHysteresis, SimdNotBuilt) { GTEST_SKIP() << "Highway not found at configure time"; }
#endif
