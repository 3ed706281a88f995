// arc_stats: every Highway target is bit-identical to the scalar reference (kernels/arc_stats.h):
// the same ArcStats, every field, in the same order, appended after the same existing entries,
// for every curve set of tests/conformance_arc_inputs.h, on the reference's splits and on random
// splits (repeated split points included, which make 1-point arcs), at several min_points.
#include <gtest/gtest.h>

#ifdef ELLIPSEKIT_HAVE_SIMD
#include "tests/conformance_arc_inputs.h"

namespace ellipsekit::conformance {
namespace {

bool SameArc(const ArcStats& a, const ArcStats& b) {
  return a.curve == b.curve && a.begin == b.begin && a.end == b.end && a.x0 == b.x0 && a.y0 == b.y0 &&
         a.x1 == b.x1 && a.y1 == b.y1 && a.xm == b.xm && a.ym == b.ym && a.min_x == b.min_x &&
         a.min_y == b.min_y && a.max_x == b.max_x && a.max_y == b.max_y && a.g0x == b.g0x && a.g0y == b.g0y &&
         a.g1x == b.g1x && a.g1y == b.g1y && a.quadrant == b.quadrant && a.sign_class == b.sign_class;
}

// The kernel appends: start from the same two stale entries on both sides.
void RunArcStats(const KernelTable& k, const Curves& curves, const Splits& splits, int min_points,
                 std::vector<ArcStats>* out) {
  ArcStats stale;
  stale.curve = -5;
  stale.min_x = 12345;
  out->assign(2, stale);
  k.arc_stats(curves, splits, min_points, out);
}

// Random split points per curve, sorted, with repeats.
Splits RandomSplits(const Curves& curves, std::uint32_t seed) {
  std::mt19937 rng(seed);
  Splits s;
  s.clear();
  for (int c = 0; c < curves.size(); ++c) {
    const std::int32_t first = curves.offset[c], n = curves.offset[c + 1] - first;
    const int count = static_cast<int>(rng() % (n / 8 + 2));
    std::vector<std::int32_t> pts;
    for (int i = 0; i < count; ++i) pts.push_back(first + static_cast<std::int32_t>(rng() % n));
    if (count > 1 && rng() % 2) pts.push_back(pts[0]);
    std::sort(pts.begin(), pts.end());
    s.index.insert(s.index.end(), pts.begin(), pts.end());
    s.offset.push_back(static_cast<std::int32_t>(s.index.size()));
  }
  return s;
}

TEST(ConformanceArcStats, AllCurveSetsAllTargets) {
  PrintCoverage("arc_stats");
  std::uint32_t seed = 1;
  std::size_t arcs_seen = 0;
  for (const CurveSet& set : ArcCurveSets()) {
    Polylines pl;
    std::vector<std::int32_t> stack;
    ScalarKernels().polyline(set.curves, PolylineToleranceQ16(Options().polyline_tolerance), &pl, &stack);
    Splits from_kernel;
    ScalarKernels().arc_split(set.curves, pl, SplitTanQ16(Options().split_angle_deg), &from_kernel);
    const std::pair<const char*, Splits> inputs[] = {
        {"arc_split splits", from_kernel}, {"random splits", RandomSplits(set.curves, seed++)}};
    for (const auto& [input_name, splits] : inputs) {
      for (int min_points : {1, 2, 5, Options().min_curve_points}) {
        std::vector<ArcStats> want;
        RunArcStats(ScalarKernels(), set.curves, splits, min_points, &want);
        arcs_seen += want.size() - 2;
        ForEachSimdTarget([&](const simd::TargetKernels& target) {
          std::vector<ArcStats> got;
          RunArcStats(target.table, set.curves, splits, min_points, &got);
          EXPECT_EQ(FirstDifference(want, got, SameArc), "")
              << set.name << ", " << input_name << ", min_points " << min_points << " [" << target.name << "]";
        });
      }
    }
  }
  EXPECT_GT(arcs_seen, 10000u);
}

}  // namespace
}  // namespace ellipsekit::conformance
#else
TEST(ConformanceArcStats, SimdNotBuilt) { GTEST_SKIP() << "Highway not found at configure time"; }
#endif
