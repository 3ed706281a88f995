// polyline: every Highway target is bit-identical to the scalar reference (kernels/polyline.h):
// the same vertices and offsets, for every curve set of tests/conformance_arc_inputs.h and a
// range of tolerances (0: every non-collinear point splits; huge: only the halving of segments
// longer than kMaxSegmentComponent splits).
#include <gtest/gtest.h>

#ifdef ELLIPSEKIT_HAVE_SIMD
#include "tests/conformance_arc_inputs.h"

namespace ellipsekit::conformance {
namespace {

// Outputs start full of stale entries: the kernel must replace them, not append.
void RunPolyline(const KernelTable& k, const Curves& curves, std::int32_t tol_q16, Polylines* out) {
  out->vertex.assign(37, -7);
  out->offset.assign(5, 99);
  std::vector<std::int32_t> stack(11, 12345);
  k.polyline(curves, tol_q16, out, &stack);
}

TEST(ConformancePolyline, AllCurveSetsAllTargets) {
  PrintCoverage("polyline");
  const std::int32_t tolerances[] = {PolylineToleranceQ16(Options().polyline_tolerance), 0, 1, 16, 64, 400,
                                     1 << 30};
  for (const CurveSet& set : ArcCurveSets()) {
    for (std::int32_t tol : tolerances) {
      Polylines want;
      RunPolyline(ScalarKernels(), set.curves, tol, &want);
      ASSERT_EQ(want.offset.size(), static_cast<std::size_t>(set.curves.size()) + 1);
      ForEachSimdTarget([&](const simd::TargetKernels& target) {
        Polylines got;
        RunPolyline(target.table, set.curves, tol, &got);
        const std::string where = set.name + " tol_q16=" + std::to_string(tol) + " [" + target.name + "]";
        EXPECT_EQ(FirstDifference(want.vertex, got.vertex), "") << where << ": vertex";
        EXPECT_EQ(FirstDifference(want.offset, got.offset), "") << where << ": offset";
      });
    }
  }
}

// The tie rule itself: on a plateau every flat point is equally far from the chord, and the
// reference (hence every target) must split at the first one. Checked against the expected
// index, not only against scalar, so a shared mistake would show too.
TEST(ConformancePolyline, FirstOfTiedFarthestPoints) {
  std::mt19937 rng(5);
  for (int flat : {1, 2, 7, 16, 31, 64, 100}) {
    Curves c;
    c.clear();
    AddPlateau(1000, 1000, 10, flat, &rng, &c);
    // tol 16 (1 px): the plateau (10 px off the chord) splits at its first point, index 10.
    std::vector<std::pair<std::string, const KernelTable*>> tables = {{"scalar", &ScalarKernels()}};
    for (const simd::TargetKernels& t : simd::Targets()) tables.emplace_back(t.name, &t.table);
    for (const auto& [name, k] : tables) {
      Polylines got;
      RunPolyline(*k, c, 16, &got);
      ASSERT_GE(got.vertex.size(), 3u) << name;
      EXPECT_EQ(got.vertex[1], 10) << "flat=" << flat << " [" << name << "]";
    }
  }
}

}  // namespace
}  // namespace ellipsekit::conformance
#else
TEST(ConformancePolyline, SimdNotBuilt) { GTEST_SKIP() << "Highway not found at configure time"; }
#endif
