// Arc selection (sec. II-B-1): curves -> polylines -> split at turning / inflection points ->
// arcs with statistics -> the T_n and OBB filters again -> quadrant classification (sec. II-B-2).
// The three arc-stage kernels (polyline, arc_split, arc_stats) come from the backend table; the
// OBB filter and the conversion to doubles are shared scalar code, so identical kernel outputs
// give identical arcs.
#pragma once

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

// Drops the curves that fail the OBB rule, in place: the kept ones move down, in order.
void FilterCurvesByObb(const Options& options, Curves* curves, std::vector<std::int64_t>* hull);

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
