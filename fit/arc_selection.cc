#include "fit/arc_selection.h"

#include <algorithm>

#include "kernels/arc_stats.h"

namespace ellipsekit {

void SetArcMoments(const Curves& curves, Arc* arc) {
  arc->moments = MomentsOfPoints(curves.x.data(), curves.y.data(), arc->begin, arc->end,
                                 (arc->min_x + arc->max_x) / 2, (arc->min_y + arc->max_y) / 2);
}

Arc ArcFromStats(const ArcStats& s, const Curves& curves) {
  Arc a;
  a.p0 = {double(s.x0), double(s.y0)};
  a.p1 = {double(s.x1), double(s.y1)};
  a.mid = {double(s.xm), double(s.ym)};
  a.n0 = Eigen::Vector2d(s.g0x, s.g0y).normalized();
  a.n1 = Eigen::Vector2d(s.g1x, s.g1y).normalized();
  a.min_x = s.min_x; a.min_y = s.min_y; a.max_x = s.max_x; a.max_y = s.max_y;
  a.width = s.max_x - s.min_x;
  a.height = s.max_y - s.min_y;
  a.quadrant = s.quadrant;
  a.begin = s.begin;
  a.end = s.end;
  SetArcMoments(curves, &a);
  return a;
}

bool PassesObbRule(const Curves& curves, int begin, int end, const Options& options,
                   std::vector<std::int64_t>* hull) {
  if (options.obb_rule == ObbRule::kMinSide) {  // decided without the box where a quick test proves it
    if (ObbShortSideAtLeast(curves.x.data(), curves.y.data(), begin, end, options.obb_threshold)) return true;
    const ObbShortSideBounds bounds = ShortSideBounds(curves.x.data(), curves.y.data(), begin, end, options.obb_threshold);
    if (bounds.lower >= options.obb_threshold) return true;
    if (bounds.upper < options.obb_threshold) return false;
  }
  const ObbSides obb = MinAreaObb(curves.x.data(), curves.y.data(), begin, end, hull);
  if (options.obb_rule == ObbRule::kMinSide) return obb.short_side >= options.obb_threshold;
  // Side ratio: an almost straight curve has a long, thin box.
  return obb.long_side <= options.obb_threshold * std::max(obb.short_side, 1.0);
}

void FilterCurvesByObb(const Options& options, Curves* curves, std::vector<std::int64_t>* hull) {
  KeepCurves(curves, [&](const Curves& c, int begin, int end) { return PassesObbRule(c, begin, end, options, hull); });
}

void DropCurvesWiderThan(double max_extent, Curves* curves) {
  KeepCurves(curves, [&](const Curves& c, int begin, int end) {
    const auto [x0, x1] = std::minmax_element(c.x.begin() + begin, c.x.begin() + end);
    const auto [y0, y1] = std::minmax_element(c.y.begin() + begin, c.y.begin() + end);
    return *x1 - *x0 <= max_extent && *y1 - *y0 <= max_extent;
  });
}

}  // namespace ellipsekit

namespace ellipsekit {

void SelectArcs(const KernelTable& kernels, const Curves& curves, const Options& options,
                ArcScratch* scratch, std::vector<Arc>* arcs, bool* capped) {
  kernels.polyline(curves, PolylineToleranceQ16(options.polyline_tolerance), &scratch->polylines,
                   &scratch->stack);
  kernels.arc_split(curves, scratch->polylines, SplitTanQ16(options.split_angle_deg), &scratch->splits);
  scratch->stats.clear();
  kernels.arc_stats(curves, scratch->splits, options.min_curve_points, &scratch->stats);
  SelectArcsFromStats(curves, options, scratch, arcs, capped);
}

void SelectArcsFromStats(const Curves& curves, const Options& options, ArcScratch* scratch,
                         std::vector<Arc>* arcs, bool* capped) {
  arcs->clear();
  for (const ArcStats& s : scratch->stats) {
    if (s.quadrant == kQuadrantNone) continue;
    // An arc that is a whole curve has passed this very test in FilterCurvesByObb (the contract of
    // `curves`): 77 % of the arcs over the shared photographs.
    const bool whole_curve = s.begin == curves.offset[s.curve] && s.end + 1 == curves.offset[s.curve + 1];
    if (!whole_curve && !PassesObbRule(curves, s.begin, s.end + 1, options, &scratch->hull)) continue;
    arcs->push_back(ArcFromStats(s, curves));
  }
  *capped = static_cast<int>(arcs->size()) > options.max_arcs;
  if (*capped) {
    // Keep the longest arcs; ties by first point index (unique), so the choice is deterministic.
    std::sort(arcs->begin(), arcs->end(), [](const Arc& a, const Arc& b) {
      return a.points() != b.points() ? a.points() > b.points() : a.begin < b.begin;
    });
    arcs->resize(static_cast<std::size_t>(options.max_arcs));
  }
}

}  // namespace ellipsekit
