// nms: every Highway target is bit-identical to the scalar reference (kernels/nms.h).
#include <gtest/gtest.h>

#ifdef ELLIPSEKIT_HAVE_SIMD
#include <random>

#include "kernels/canny_thresholds.h"
#include "tests/conformance_util.h"

namespace ellipsekit::conformance {
namespace {

void CheckNms(const std::string& what, const Gradients& g, const NmsThresholds& th, int out_pad) {
  const std::ptrdiff_t out_stride = g.width + out_pad;
  ExpectAllTargetsMatchScalar("nms " + what, [&](const KernelTable& k) {
    std::vector<Plane> out;
    out.push_back(MakePlane<std::uint8_t>("out", g.width, g.height, out_stride));
    k.nms(g.dx.data(), g.dy.data(), g.mag.data(), g.width, g.height, g.stride, th, out[0].data<std::uint8_t>(),
          out_stride);
    return out;
  });
}

void CheckOnePair(const std::string& what, const Gradients& g, int low, int high, int out_pad) {
  const NmsOnePair pair{low, high};
  CheckNms(what + " low=" + std::to_string(low) + " high=" + std::to_string(high), g, pair.view(), out_pad);
}

// Tiles of 32 px with a different pair each (drawn from [0, range]): runs that start and end at
// tile borders, inside a vector's reach of the frame's first and last columns.
void CheckTiles(const std::string& what, const Gradients& g, int range, std::uint32_t seed, int out_pad) {
  CannyTiles tiles;
  tiles.Resize(g.width, g.height, kNmsMinTileShift);
  std::mt19937 rng(seed);
  for (std::size_t t = 0; t < tiles.high.size(); ++t) {
    tiles.high[t] = static_cast<std::int32_t>(rng() % static_cast<std::uint32_t>(range + 1));
    tiles.low[t] = tiles.high[t] / 2;
  }
  CheckNms(what + " 32 px tiles", g, tiles.view(), out_pad);
}

TEST(ConformanceNms, AllImagesAllTargets) {
  std::uint32_t seed = 300;
  for (const ImageCase& c : ConformanceImages()) {
    const Gradients g = GradientsOf(c);
    const CannyTiles tiles = TilesOf(g);
    CheckOnePair(SizeOf(c), g, tiles.frame.low, tiles.frame.high, c.out_pad);
    CheckNms(SizeOf(c) + " 64 px tiles as detect() picks them", g, tiles.view(), c.out_pad);
    CheckOnePair(SizeOf(c), g, 0, 0, c.out_pad);  // every local maximum counts
    CheckTiles(SizeOf(c), g, 60, seed++, c.out_pad);
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
      CheckOnePair(what, g, 0, range, 3);
      CheckOnePair(what, g, range / 2, range, 0);
      CheckTiles(what, g, range, seed++, 2);
    }
  }
  for (int w = 1; w <= 70; ++w) {
    const Gradients g = RandomGradients(w, 4, w, 3, seed++);
    CheckOnePair("random w=" + std::to_string(w), g, 0, 2, 1);
    CheckTiles("random w=" + std::to_string(w), g, 3, seed++, 1);
  }
}

}  // namespace
}  // namespace ellipsekit::conformance
#else
TEST(ConformanceNms, SimdNotBuilt) { GTEST_SKIP() << "Highway not found at configure time"; }
#endif
