// arc_split: every Highway target is bit-identical to the scalar reference (kernels/arc_split.h):
// the same split indices (order and dedup included) and offsets, for every curve set of
// tests/conformance_arc_inputs.h, on the reference's polylines at several tolerances and on
// random polylines (vertex gaps 1..3 and 1..40, within the 1024 segment bound), at several
// split angles. simd::ArcSplit is called directly: the SIMD kernel table keeps the reference for
// arc_split (faster on typical curves, see cpu/arc_split.cc).
#include <gtest/gtest.h>

#ifdef ELLIPSEKIT_HAVE_SIMD
#include "tests/conformance_arc_inputs.h"

namespace ellipsekit::conformance {
namespace {

// Outputs start full of stale entries: the kernel must replace them, not append.
using ArcSplitFn = void (*)(const Curves&, const Polylines&, std::int64_t, Splits*);

void RunArcSplit(ArcSplitFn arc_split, const Curves& curves, const Polylines& pl, std::int64_t tan_q16,
                 Splits* out) {
  out->index.assign(23, -3);
  out->offset.assign(4, 77);
  arc_split(curves, pl, tan_q16, out);
}

// Every curve's first and last point plus random points in between, gaps in [1, max_gap].
Polylines RandomPolylines(const Curves& curves, int max_gap, std::uint32_t seed) {
  std::mt19937 rng(seed);
  Polylines pl;
  pl.clear();
  for (int c = 0; c < curves.size(); ++c) {
    const std::int32_t first = curves.offset[c], last = curves.offset[c + 1] - 1;
    pl.vertex.push_back(first);
    for (std::int32_t i = first; i < last;) {
      i = std::min(last, i + 1 + static_cast<std::int32_t>(rng() % max_gap));
      pl.vertex.push_back(i);
    }
    pl.offset.push_back(static_cast<std::int32_t>(pl.vertex.size()));
  }
  return pl;
}

TEST(ConformanceArcSplit, AllCurveSetsAllTargets) {
  PrintCoverage("arc_split");
  const double angles[] = {Options().split_angle_deg, 1.0, 10.0, 20.0, 45.0, 60.0};
  std::uint32_t seed = 1;
  int splits_seen = 0;
  for (const CurveSet& set : ArcCurveSets()) {
    std::vector<std::pair<std::string, Polylines>> inputs;
    for (double tol : {Options().polyline_tolerance, 0.0, 2.0}) {
      Polylines pl;
      std::vector<std::int32_t> stack;
      ScalarKernels().polyline(set.curves, PolylineToleranceQ16(tol), &pl, &stack);
      inputs.emplace_back("polyline tol " + std::to_string(tol), std::move(pl));
    }
    inputs.emplace_back("random gaps 1..3", RandomPolylines(set.curves, 3, seed++));
    inputs.emplace_back("random gaps 1..40", RandomPolylines(set.curves, 40, seed++));
    for (const auto& [input_name, pl] : inputs) {
      for (double angle : angles) {
        const std::int64_t tan_q16 = SplitTanQ16(angle);
        Splits want;
        RunArcSplit(scalar::ArcSplit, set.curves, pl, tan_q16, &want);
        ASSERT_EQ(want.offset.size(), static_cast<std::size_t>(set.curves.size()) + 1);
        splits_seen += static_cast<int>(want.index.size());
        ForEachSimdTarget([&](const simd::TargetKernels& target) {
          Splits got;
          RunArcSplit(target.arc_split, set.curves, pl, tan_q16, &got);
          const std::string where =
              set.name + ", " + input_name + ", angle " + std::to_string(angle) + " [" + target.name + "]";
          EXPECT_EQ(FirstDifference(want.index, got.index), "") << where << ": index";
          EXPECT_EQ(FirstDifference(want.offset, got.offset), "") << where << ": offset";
        });
      }
    }
  }
  EXPECT_GT(splits_seen, 1000);  // the inputs do split (else the comparison proves little)
}

}  // namespace
}  // namespace ellipsekit::conformance
#else
TEST(ConformanceArcSplit, SimdNotBuilt) { GTEST_SKIP() << "Highway not found at configure time"; }
#endif
