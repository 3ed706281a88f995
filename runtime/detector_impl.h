// Detector::Impl: the buffers and the steps of one Detector. runtime/detector.cc holds the steps
// of one pyramid level, split into the pixel stage and the back end, runtime/detector_checks.cc
// the back end's last checks, runtime/detector_crowd.cc its crowd pass; runtime/detector_pyramid.cc
// the pyramid levels around them; runtime/stream.cc runs the two stages of several Detectors on
// two threads. Private to the library.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "ellipsekit/detector.h"
#include "fit/arc_selection.h"
#include "fit/closed_outlines.h"
#include "fit/clustering.h"
#include "fit/curve_tracing.h"
#include "fit/edge_coverage.h"
#include "fit/edge_map_view.h"
#include "fit/edge_refit.h"
#include "fit/grouping.h"
#include "kernels/canny_thresholds.h"
#include "kernels/kernel_table.h"
#ifdef ELLIPSEKIT_HAVE_VULKAN
#include "runtime/vulkan_arc_stage.h"
#include "runtime/vulkan_edge_stage.h"
#endif

namespace ellipsekit {

// Options::pyramid_level: at most this many levels, none shorter than kMinPyramidSide px.
inline constexpr int kMaxPyramidLevel = 4;
inline constexpr int kMinPyramidSide = 64;

// The crowd pass's trigger counts the short curves of at least this many points (and fewer than
// T_n), whatever crowd_min_curve_points the pass itself traces with: the counts it was measured on
// (docs/crowded-scenes.md); curves of 10-11 points are common in photographs' texture.
inline constexpr int kCrowdTriggerMinPoints = 12;
// Options::crowd_closed_min_support: the pieces of a small closed outline are the crowd pass's
// curves and its dropped curves of at least this many points.
inline constexpr int kClosedMinPiecePoints = 5;

// An axis-aligned box, for cheap "could these two ellipses touch" tests.
struct Box {
  double x0, y0, x1, y1;
  bool Intersects(const Box& o) const { return x0 <= o.x1 && o.x0 <= x1 && y0 <= o.y1 && o.y0 <= y1; }
};

// The bounding box of e, grown by `margin` px on every side.
inline Box BoundingBox(const Ellipse& e, double margin) {
  const double c = std::cos(e.theta), s = std::sin(e.theta);
  const double hx = std::sqrt(e.a * e.a * c * c + e.b * e.b * s * s) + margin;
  const double hy = std::sqrt(e.a * e.a * s * s + e.b * e.b * c * c) + margin;
  return {e.cx - hx, e.cy - hy, e.cx + hx, e.cy + hy};
}

// The same object found twice (on two pyramid levels, or by the crowd pass and the main one):
// centres within 0.25 b, axes within 25 %.
inline bool Overlapping(const Ellipse& v, const Ellipse& w) {
  const double b = std::min(v.b, w.b);
  return std::hypot(v.cx - w.cx, v.cy - w.cy) < 0.25 * b && std::abs(v.a - w.a) < 0.25 * std::max(v.a, w.a) &&
         std::abs(v.b - w.b) < 0.25 * std::max(v.b, w.b);
}

// Whether one of found[0, n) is e (Overlapping) or, with rims, a rim around it (SurroundsAsRim,
// fit/clustering.h). Both need centres within 0.25 e.b: a box test first spares the others their
// roots (in a crowd, n is hundreds for each of hundreds of e).
inline bool FoundAlready(const Ellipse* found, std::size_t n, const Ellipse& e, bool rims = false) {
  for (std::size_t i = 0; i < n; ++i) {
    const Ellipse& f = found[i];
    if (!(std::abs(f.cx - e.cx) < 0.25 * e.b && std::abs(f.cy - e.cy) < 0.25 * e.b)) continue;
    if (Overlapping(f, e) || (rims && SurroundsAsRim(f, e))) return true;
  }
  return false;
}

struct Detector::Impl {
  Options options;
  Status status;
  const KernelTable* kernels = nullptr;
  std::string backend_note;  // why the backend or target differs from the one asked for
#ifdef ELLIPSEKIT_HAVE_VULKAN
  std::unique_ptr<VulkanEdgeStage> vulkan;  // set when the edge stage runs on a Vulkan device
  // Set when the arc stage runs on the device too; null (device without shaderInt64) -> the CPU
  // table runs it, with identical results (every arc-stage kernel is integer-exact).
  std::unique_ptr<VulkanArcStage> vulkan_arcs;
#endif
  int width = 0, height = 0;
  std::vector<std::uint8_t> blurred, nms, edge_map;
  std::vector<std::uint8_t> pyramid[kMaxPyramidLevel];  // level l + 1 of the input (Options::pyramid_level)
  std::unique_ptr<Impl> coarse[kMaxPyramidLevel];       // Options::coarse_levels
  DetectionResult coarse_result;
  std::vector<std::int16_t> dx, dy;
  std::vector<std::uint16_t> mag;
  std::vector<std::uint32_t> hist;
  CannyTiles tiles;
  std::vector<std::int32_t> stack;
  Curves curves;
  TraceScratch trace;
  std::vector<std::int64_t> hull;
  ArcScratch arc_scratch;
  std::vector<Arc> arcs;
  GroupScratch groups;
  std::vector<Candidate> candidates;
  ClusterScratch cluster_scratch;
  EdgeClaims claims;  // Options::min_exclusive_coverage; scratch of RefitToEdges
  EdgeRefitScratch refit_scratch;
  std::vector<std::pair<double, int>> by_coverage;  // (rank, kept index): KeepExclusivelySupported
  std::vector<Box> boxes;  // per kept candidate: CompleteOuterRims' rim reach, then the claim reach
  std::vector<std::uint8_t> dropped;
  std::vector<std::uint8_t> claimed_near;  // coarse levels: which kept ellipses claimed their edges
  // Options::crowd_min_curve_points: the crowd pass runs the back end a second time on these
  // buffers (the first pass's curves, arcs and candidates are spent once its ellipses are out).
  DetectionResult crowd_result;
  std::vector<double> minor_axes;  // the crowd pass's semi-minor axes, sorted
  // Options::crowd_closed_min_support: the crowd pass's curves and short curves, their groups' fits.
  Curves closed_pieces;
  bool coarse_level = false;  // a coarse pyramid level's Detector (Options::coarse_levels): BackEndAt only
  ClosedOutlineScratch closed_scratch;
  std::vector<Ellipse> closed_fits;

  // The first frame of a size sizes the buffers (detector.cc).
  void Resize(int w, int h);

  // One frame: the pixel stage (edges, curves), then the back end (arcs, grouping to the final
  // ellipses). runtime/stream.cc runs the two on different threads, for different frames, each
  // frame on an Impl of its own; the back end reads what the pixel stage left in this Impl.
  Status Detect(const ImageView& input, DetectionResult* result) {
    const Status st = PixelStage(input);
    return st.ok() ? BackEnd(result) : st;
  }
  Status PixelStage(const ImageView& input);  // detector_pyramid.cc: the level, then PixelStageAt
  Status BackEnd(DetectionResult* result);    // detector_pyramid.cc: BackEndAt, coarse levels
  // detector.cc, one level: edges and curves (and arcs when they run on the device), then the
  // (CPU) arcs and the back end.
  Status PixelStageAt(const ImageView& image);
  void BackEndAt(DetectionResult* result);
  int PyramidLevel(const ImageView& input) const;
  ImageView Reduce(const ImageView& input, int level);

  // What the pixel stage of the current frame left for its back end.
  struct Front {
    ImageView input;  // the caller's frame (Options::refit_to_image reads it after the back end)
    ImageView image;  // the level it ran on (in `pyramid`, or the caller's frame at level 0)
    int level = 0;
    Backend ran = Backend::kScalar, arcs_ran = Backend::kScalar;
    bool arcs_capped = false;
    bool arcs_done = false;  // the arc stage ran on the device; else the back end runs it
    int edge_pixels = 0;
    double noise_sigma = 0;  // Options::denoise_min_sigma
    int denoise_passes = 0;
    int short_curves = 0;  // curves of crowd_min_curve_points to min_curve_points - 1 points
    double total_ms = 0, edges_ms = 0, curves_ms = 0, arcs_ms = 0;
  } front;
  void CompleteOuterRims(int kept, GroupStats* stats);  // detector_checks.cc
  bool HoldsAnother(int i, int kept) const;             // detector_checks.cc
  // Whether e is nearly the same ellipse as one of candidates[0, kept) other than i.
  bool DetectedElsewhere(const Ellipse& e, int i, int kept) const;  // detector_checks.cc
  int KeepExclusivelySupported(int kept);              // detector_checks.cc
  int DropStriped(int kept);                           // detector_checks.cc
  void AddCrowdPass(DetectionResult* result);                           // detector_crowd.cc
  void AddClosedOutlines(double min_support, DetectionResult* result);  // detector_crowd.cc, the end of AddCrowdPass
  EdgeMapView EdgeView() const { return {edge_map.data(), width, dx.data(), dy.data(), width, width, height}; }
};

}  // namespace ellipsekit
