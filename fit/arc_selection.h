// Arc selection (sec. II-B-1): curves -> polylines -> split at turning / inflection points ->
// arcs with statistics -> the T_n and OBB filters again -> quadrant classification (sec. II-B-2).
// The three arc-stage kernels (polyline, arc_split, arc_stats) come from the backend table; the
// OBB filter and the conversion to doubles are shared scalar code, so identical kernel outputs
// give identical arcs.
#pragma once

#include <algorithm>
#include <vector>

#include "ellipsekit/options.h"
#include "fit/arc.h"
#include "fit/obb.h"
#include "kernels/arc_split.h"
#include "kernels/polyline.h"
#include "kernels/kernel_table.h"

namespace ellipsekit {

// True when the OBB_min of points [begin, end) passes the T_O rule of `options`.
bool PassesObbRule(const Curves& curves, int begin, int end, const Options& options,
                   std::vector<std::int64_t>* hull);

// Keeps the curves for which keep(curves, begin, end) holds (points [begin, end)), in place: the
// kept ones move down, in order. No allocation.
template <typename Keep>
void KeepCurves(Curves* curves, Keep keep) {
  Curves& c = *curves;
  int kept = 0;
  std::int32_t to = 0;  // where the next kept curve's points go (<= where they are)
  for (int i = 0; i < c.size(); ++i) {
    const std::int32_t b = c.offset[i], e = c.offset[i + 1];
    if (!keep(static_cast<const Curves&>(c), b, e)) continue;
    if (to != b) {
      std::copy(c.x.begin() + b, c.x.begin() + e, c.x.begin() + to);
      std::copy(c.y.begin() + b, c.y.begin() + e, c.y.begin() + to);
      std::copy(c.gx.begin() + b, c.gx.begin() + e, c.gx.begin() + to);
      std::copy(c.gy.begin() + b, c.gy.begin() + e, c.gy.begin() + to);
    }
    c.sign_class[kept] = c.sign_class[i];
    to += e - b;
    c.offset[++kept] = to;  // offset[i + 1] was read above, before this write can reach it
  }
  c.x.resize(static_cast<std::size_t>(to));
  c.y.resize(static_cast<std::size_t>(to));
  c.gx.resize(static_cast<std::size_t>(to));
  c.gy.resize(static_cast<std::size_t>(to));
  c.sign_class.resize(static_cast<std::size_t>(kept));
  c.offset.resize(static_cast<std::size_t>(kept) + 1);
}

// Drops the curves that fail the OBB rule, in place: the kept ones move down, in order.
void FilterCurvesByObb(const Options& options, Curves* curves, std::vector<std::int64_t>* hull);

// Drops the curves whose bounding box is more than max_extent px wide or high, in place.
void DropCurvesWiderThan(double max_extent, Curves* curves);

struct ArcScratch {
  Polylines polylines;
  Splits splits;
  std::vector<std::int32_t> stack;
  std::vector<ArcStats> stats;
  std::vector<std::int64_t> hull;
};

// Builds the arcs of `curves`, keeping at most options.max_arcs (longest first; sets *capped).
// `curves` are FilterCurvesByObb's output for the same options: an arc that spans a whole curve
// is not tested against the OBB rule again.
void SelectArcs(const KernelTable& kernels, const Curves& curves, const Options& options, ArcScratch* scratch,
                std::vector<Arc>* arcs, bool* capped);

// The part of SelectArcs after the kernels: scratch->stats (filled by the three arc-stage kernels on
// any backend, e.g. runtime/vulkan_arc_stage.h) -> quadrant and OBB filters -> the max_arcs cap.
void SelectArcsFromStats(const Curves& curves, const Options& options, ArcScratch* scratch,
                         std::vector<Arc>* arcs, bool* capped);

}  // namespace ellipsekit
