// edge_sign: every Highway target is bit-identical to the scalar reference (kernels/edge_sign.h),
// also when the output aliases the edge map (the detector's way of calling it).
#include <gtest/gtest.h>

#ifdef ELLIPSEKIT_HAVE_SIMD
#include "kernels/canny_thresholds.h"
#include "tests/conformance_util.h"

namespace ellipsekit::conformance {
namespace {

// edges: width x height bytes, rows edge_stride apart.
void CheckEdgeSign(const std::string& what, const std::vector<std::uint8_t>& edges, std::ptrdiff_t edge_stride,
                   const Gradients& g, int out_pad) {
  const std::ptrdiff_t out_stride = g.width + out_pad;
  ExpectAllTargetsMatchScalar("edge_sign " + what, [&](const KernelTable& k) {
    std::vector<Plane> out;
    out.push_back(MakePlane<std::uint8_t>("out", g.width, g.height, out_stride));
    k.edge_sign(edges.data(), edge_stride, g.dx.data(), g.dy.data(), g.stride, g.width, g.height,
                out[0].data<std::uint8_t>(), out_stride);
    return out;
  });
  ExpectAllTargetsMatchScalar("edge_sign in place " + what, [&](const KernelTable& k) {
    std::vector<Plane> out;
    out.push_back(MakePlane<std::uint8_t>("out", g.width, g.height, edge_stride));
    std::uint8_t* o = out[0].data<std::uint8_t>();
    for (int y = 0; y < g.height; ++y) std::memcpy(o + y * edge_stride, edges.data() + y * edge_stride, g.width);
    k.edge_sign(o, edge_stride, g.dx.data(), g.dy.data(), g.stride, g.width, g.height, o, edge_stride);
    return out;
  });
}

TEST(ConformanceEdgeSign, AllImagesAllTargets) {
  for (const ImageCase& c : ConformanceImages()) {
    const Gradients g = GradientsOf(c);
    const CannyTiles tiles = TilesOf(g);
    const std::ptrdiff_t edge_stride = g.width + 2;
    std::vector<std::uint8_t> edges(static_cast<std::size_t>(edge_stride) * g.height, 0);
    std::vector<std::int32_t> stack(static_cast<std::size_t>(g.width) * g.height);
    ScalarKernels().nms(g.dx.data(), g.dy.data(), g.mag.data(), g.width, g.height, g.stride, tiles.view(),
                        edges.data(), edge_stride);
    ScalarKernels().hysteresis(edges.data(), g.width, g.height, edge_stride, stack.data());
    CheckEdgeSign(SizeOf(c), edges, edge_stride, g, c.out_pad);
  }
}

// Random 0/1 edges over random gradients with many zero components.
TEST(ConformanceEdgeSign, RandomEdgesAndGradients) {
  std::uint32_t seed = 300;
  for (int w = 1; w <= 70; ++w) {
    for (int range : {1, 1020}) {
      const Gradients g = RandomGradients(w, 3, w + 1, range, seed++);
      std::vector<std::uint8_t> edges(static_cast<std::size_t>(w) * 3);
      std::mt19937 rng(seed++);
      for (auto& e : edges) e = static_cast<std::uint8_t>(rng() & 1);
      CheckEdgeSign("random w=" + std::to_string(w) + " range=" + std::to_string(range), edges, w, g, 2);
    }
  }
}

}  // namespace
}  // namespace ellipsekit::conformance
#else
TEST(ConformanceEdgeSign, SimdNotBuilt) { GTEST_SKIP() << "Highway not found at configure time"; }
#endif
