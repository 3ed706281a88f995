// Frame orchestration on one pyramid level: the pixel stage (edges -> curves -> arcs) and the back
// end (candidates -> clusters -> checks), with stage timings; option and image validation; the
// Detector's public methods. Every buffer lives in Detector::Impl (runtime/detector_impl.h) and is
// sized on the first frame of a given size; the vectors only clear() afterwards, so later frames
// of that size reuse their capacity (or grow once, and keep it, for a busier frame).
#include "ellipsekit/detector.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>

#include "fit/flat_stretches.h"
#include "fit/obb.h"
#include "kernels/canny_thresholds.h"
#include "kernels/noise_sigma.h"
#include "runtime/backend.h"
#include "runtime/coverage_check.h"
#include "runtime/detector_impl.h"

namespace ellipsekit {

namespace {


using Clock = std::chrono::steady_clock;

double Ms(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// Resize: one pixel in kEdgeShare is expected on an edge of a busy frame.
constexpr std::size_t kEdgeShare = 8;

Status Invalid(const std::string& what) { return {StatusCode::kInvalidArgument, what}; }

bool Finite(double v) { return std::isfinite(v); }

bool SameGeometry(const Ellipse& u, const Ellipse& v) {
  return u.cx == v.cx && u.cy == v.cy && u.a == v.a && u.b == v.b && u.theta == v.theta;
}

// Best score first; equal scores keep their order (the clustering's, by K + psi). Insertion sort:
// stable without a buffer (std::stable_sort may allocate); a frame keeps at most a few hundred
// ellipses, most of them at the top score, so few are moved.
void SortByScore(std::vector<Ellipse>* ellipses) {
  std::vector<Ellipse>& v = *ellipses;
  for (std::size_t i = 1; i < v.size(); ++i) {
    const Ellipse e = v[i];
    std::size_t j = i;
    for (; j > 0 && v[j - 1].score < e.score; --j) v[j] = v[j - 1];
    v[j] = e;
  }
}

}  // namespace

std::size_t ReserveFor(int cap) {
  return static_cast<std::size_t>(std::min(cap, kMaxReserved));
}

Status ValidateOptions(const Options& o) {
  if (o.canny_high_permille < 0 || o.canny_high_permille > 1000) return Invalid("canny_high_permille must be in [0, 1000]");
  if (o.canny_low_permille < 0 || o.canny_low_permille > 1000) return Invalid("canny_low_permille must be in [0, 1000]");
  if (o.canny_min_high < 0 || o.canny_min_high > kMaxMagnitude) return Invalid("canny_min_high must be in [0, 2040]");
  if (o.canny_contrast_ref < 0 || o.canny_contrast_ref > kMaxMagnitude)
    return Invalid("canny_contrast_ref must be in [0, 2040] (0: a fixed floor)");
  if (o.canny_tile != 0 && (o.canny_tile < 32 || o.canny_tile > 16384 || (o.canny_tile & (o.canny_tile - 1)) != 0))
    return Invalid("canny_tile must be 0 (one pair of thresholds per frame) or a power of two from 32 to 16384");
  if (!Finite(o.denoise_min_sigma)) return Invalid("denoise_min_sigma must be a finite number (<= 0: never smooth more)");
  if (o.min_curve_points < 3) return Invalid("min_curve_points (T_n) must be >= 3");
  if (!Finite(o.obb_threshold) || o.obb_threshold < 0) return Invalid("obb_threshold (T_O) must be a finite number >= 0");
  if (!Finite(o.polyline_tolerance) || o.polyline_tolerance <= 0 || o.polyline_tolerance > 4)
    return Invalid("polyline_tolerance must be in (0, 4] px");
  if (!Finite(o.split_angle_deg) || o.split_angle_deg <= 0 || o.split_angle_deg > 60)
    return Invalid("split_angle_deg (T_theta) must be in (0, 60] degrees");
  if (o.crowd_min_curve_points < 3) return Invalid("crowd_min_curve_points must be >= 3 (>= min_curve_points: no crowd pass)");
  if (o.crowd_min_short_curves < 0) return Invalid("crowd_min_short_curves must be >= 0");
  if (!Finite(o.crowd_max_minor_axis) || o.crowd_max_minor_axis < 0) return Invalid("crowd_max_minor_axis must be a finite number >= 0 px");
  if (o.crowd_min_small_found < 0) return Invalid("crowd_min_small_found must be >= 0");
  if (o.crowd_min_similar < 0) return Invalid("crowd_min_similar must be >= 0");
  if (std::isnan(o.pair_reach) || !(o.pair_reach > 0)) return Invalid("pair_reach must be > 0 (inf: no reach limit)");
  if (!Finite(o.center_distance) || o.center_distance <= 0) return Invalid("center_distance (T_c) must be > 0");
  if (!Finite(o.mean_shift_bandwidth) || o.mean_shift_bandwidth <= 0) return Invalid("mean_shift_bandwidth must be > 0");
  if (!Finite(o.distance_ratio) || o.distance_ratio < 1) return Invalid("distance_ratio (T_f) must be >= 1");
  if (!Finite(o.length_ratio) || o.length_ratio < 0) return Invalid("length_ratio (T_l) must be >= 0");
  if (!Finite(o.inlier_threshold) || o.inlier_threshold <= 0) return Invalid("inlier_threshold (T_d) must be > 0");
  if (!Finite(o.circumference_ratio) || o.circumference_ratio < 0 || o.circumference_ratio > 1)
    return Invalid("circumference_ratio (T_psi) must be in [0, 1]");
  if (!Finite(o.refined_circumference_ratio) || o.refined_circumference_ratio < 0 || o.refined_circumference_ratio > 1)
    return Invalid("refined_circumference_ratio must be in [0, 1]");
  if (!Finite(o.cluster_distance) || o.cluster_distance < 0) return Invalid("cluster_distance (T_s) must be >= 0");
  if (!Finite(o.cluster_relative) || o.cluster_relative < 0 || o.cluster_relative > 1)
    return Invalid("cluster_relative must be in [0, 1]");
  if (!Finite(o.cluster_outer_margin)) return Invalid("cluster_outer_margin must be a finite number");
  if (!Finite(o.min_edge_coverage) || o.min_edge_coverage < 0 || o.min_edge_coverage > 1)
    return Invalid("min_edge_coverage must be in [0, 1]");
  if (!Finite(o.frame_cut_min_inside) || o.frame_cut_min_inside < 0 || o.frame_cut_min_inside > 1)
    return Invalid("frame_cut_min_inside must be in [0, 1] (1: off)");
  if (!Finite(o.min_exclusive_coverage) || o.min_exclusive_coverage < 0 || o.min_exclusive_coverage > 1)
    return Invalid("min_exclusive_coverage must be in [0, 1]");
  if (!Finite(o.max_striped_share) || o.max_striped_share < 0 || o.max_striped_share > 1)
    return Invalid("max_striped_share must be in [0, 1] (1: off)");
  if (!Finite(o.max_nested_striped_share) || o.max_nested_striped_share < 0 || o.max_nested_striped_share > 1)
    return Invalid("max_nested_striped_share must be in [0, 1] (1: off)");
  if (!Finite(o.pair_min_edge_coverage) || o.pair_min_edge_coverage < 0 || o.pair_min_edge_coverage > 1)
    return Invalid("pair_min_edge_coverage must be in [0, 1]");
  if (!Finite(o.closed_min_support) || o.closed_min_support < 0)
    return Invalid("closed_min_support must be a finite number >= 0 (> 1 turns it off)");
  if (!Finite(o.crowd_closed_min_support) || o.crowd_closed_min_support < 0)
    return Invalid("crowd_closed_min_support must be a finite number >= 0 (> 1 turns it off)");
  if (!Finite(o.rescue_min_coverage) || o.rescue_min_coverage < 0)
    return Invalid("rescue_min_coverage must be a finite number >= 0 (> 1 turns the second chance off)");
  if (!Finite(o.min_axis_ratio) || o.min_axis_ratio < 0 || o.min_axis_ratio > 1)
    return Invalid("min_axis_ratio must be in [0, 1]");
  if (!Finite(o.rim_min_coverage) || o.rim_min_coverage < 0)
    return Invalid("rim_min_coverage must be >= 0 (> 1 turns the outer-rim search off)");
  if (o.max_arcs < 1 || o.max_pairs < 1 || o.max_triplets < 1 || o.max_candidates < 1 || o.max_mean_shift_iterations < 1)
    return Invalid("caps (max_arcs, max_pairs, max_triplets, max_candidates, max_mean_shift_iterations) must be >= 1");
  if (o.max_image_pixels < 1) return Invalid("max_image_pixels must be >= 1");
  if (o.pyramid_level < -1 || o.pyramid_level > kMaxPyramidLevel) return Invalid("pyramid_level must be in [-1, 4] (-1: auto)");
  if (o.pyramid_max_pixels < 1) return Invalid("pyramid_max_pixels must be >= 1");
  if (o.coarse_levels < 0 || o.coarse_levels > kMaxPyramidLevel) return Invalid("coarse_levels must be in [0, 4]");
  if (o.coarse_min_pixels < 0) return Invalid("coarse_min_pixels must be >= 0");
  switch (o.backend) {
    case Backend::kAuto: case Backend::kScalar: case Backend::kSimd: case Backend::kVulkan: break;
    default: return Invalid("backend is not one of Auto, Scalar, Simd, Vulkan");
  }
  if (o.center_method != CenterMethod::kLongestChords && o.center_method != CenterMethod::kArcChords)
    return Invalid("center_method is not one of LongestChords, ArcChords");
  if (o.obb_rule != ObbRule::kMinSide && o.obb_rule != ObbRule::kSideRatio)
    return Invalid("obb_rule is not one of MinSide, SideRatio");
  if (o.inlier_rule != InlierRule::kAlgebraic && o.inlier_rule != InlierRule::kPixel)
    return Invalid("inlier_rule is not one of Algebraic, Pixel");
  if (o.cluster_rule != ClusterRule::kFeatureDistance && o.cluster_rule != ClusterRule::kRelative)
    return Invalid("cluster_rule is not one of FeatureDistance, Relative");
  return Status::Ok();
}

Status ValidateImage(const ImageView& image, const Options& options) {
  if (image.data == nullptr) return Invalid("image data is null");
  if (image.width <= 0 || image.height <= 0)
    return Invalid("image size " + std::to_string(image.width) + "x" + std::to_string(image.height) + " is not positive");
  if (image.stride < image.width)
    return Invalid("image stride " + std::to_string(image.stride) + " is smaller than its width " + std::to_string(image.width));
  // The last pixel, (height - 1) * stride + width - 1 bytes past data, must be addressable: a
  // stride so large that this overflows (e.g. PTRDIFF_MAX) would wrap the row pointers.
  if (image.height > 1 && image.stride > (PTRDIFF_MAX - image.width) / (image.height - 1))
    return Invalid("image stride " + std::to_string(image.stride) + " times its height " +
                   std::to_string(image.height) + " overflows the address range");
  if (image.width > kMaxImageDimension || image.height > kMaxImageDimension)
    return Invalid("image size " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                   " exceeds the maximum side of " + std::to_string(kMaxImageDimension) + " px");
  if (static_cast<long long>(image.width) * image.height > options.max_image_pixels)
    return Invalid("image has " + std::to_string(static_cast<long long>(image.width) * image.height) +
                   " pixels, more than max_image_pixels = " + std::to_string(options.max_image_pixels));
  return Status::Ok();
}

// The first frame of a size sizes two kinds of buffer. Per-pixel planes hold what they must
// (15 bytes per pixel: three 1-byte maps, three 2-byte gradient planes, the hysteresis stack of
// 4-byte indices, the claims mask; the tracer's bordered copy is sized by TraceCurves itself).
// Buffers of edge points, curves and arcs are reserved for a busy frame (kEdgeShare of its
// pixels on edges) and, when a frame holds more, grow geometrically (std::vector) and keep what
// they grew to; buffers bounded by a cap are reserved up to the cap (ReserveFor). Never the
// worst case of this many pixels: that cost ~613 bytes per pixel (bench memory/<backend>/...).
void Detector::Impl::Resize(int w, int h) {
  if (w == width && h == height) return;
  width = w;
  height = h;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  blurred.resize(n); nms.resize(n); edge_map.resize(n);
  dx.resize(n); dy.resize(n); mag.resize(n);
  hist.resize(kMaxMagnitude + 1);
  tiles.Resize(w, h, options);
  stack.resize(n);  // hysteresis, then ClassifyFlatStretches: every pixel at most once
  claims.Resize(w, h);
  refit_scratch.Reserve(w, h);
  // Edge pixels after NMS: 1-6 % of a photograph's or a crowded frame's pixels, up to 22 % on
  // the noisiest generated scenes (measured: `ellipsekit detect --format json`, counts).
  const std::size_t points = n / kEdgeShare;
  const int shortest_curve = std::min(options.min_curve_points, options.crowd_min_curve_points);  // the crowd pass's
  const std::size_t curve_count = points / static_cast<std::size_t>(std::max(3, shortest_curve)) + 1;
  const std::size_t long_curve = std::min<std::size_t>(points, 4 * (static_cast<std::size_t>(w) + h));
  const std::size_t arc_count = std::min<std::size_t>(points / 8, ReserveFor(options.max_arcs));
  curves.x.reserve(points); curves.y.reserve(points); curves.gx.reserve(points); curves.gy.reserve(points);
  curves.offset.reserve(curve_count + 1); curves.sign_class.reserve(curve_count);
  trace.forward.reserve(long_curve);
  trace.backward.reserve(long_curve);
  const auto obb_scratch = static_cast<std::size_t>(ObbScratchSize(long_curve, std::min<std::size_t>(long_curve, w)));
  hull.reserve(obb_scratch);
  arc_scratch.hull.reserve(obb_scratch);
  arc_scratch.polylines.vertex.reserve(points / 4);
  arc_scratch.polylines.offset.reserve(curve_count + 1);
  arc_scratch.splits.index.reserve(points / 4);
  arc_scratch.splits.offset.reserve(curve_count + 1);
  arc_scratch.stack.reserve(2 * long_curve);
  arc_scratch.stats.reserve(arc_count);
  arcs.reserve(arc_count);
  candidates.reserve(ReserveFor(options.max_candidates));
  cluster_scratch.Reserve(ReserveFor(options.max_candidates));
  by_coverage.reserve(ReserveFor(options.max_candidates));
  minor_axes.reserve(2 * ReserveFor(options.max_candidates));
  crowd_result.ellipses.reserve(ReserveFor(options.max_candidates));
  boxes.reserve(ReserveFor(options.max_candidates));
  dropped.reserve(ReserveFor(options.max_candidates));
  claimed_near.reserve(2 * ReserveFor(options.max_candidates));
  groups.Reserve(w, h, options);
  // The crowd pass's pieces for the closed outlines: its curves and short curves, each edge pixel
  // in one of them; a fitted group holds at least kClosedMinPoints of them. Not on a coarse level
  // (BackEnd runs the crowd pass on the working level only) nor with the outlines off.
  const bool closed_outlines = !coarse_level && options.crowd_min_curve_points < options.min_curve_points &&
                               (options.crowd_closed_min_support <= 1 || options.closed_min_support <= 1);
  if (!closed_outlines) return;
  const std::size_t piece_count = points / kClosedMinPiecePoints + 1;
  closed_pieces.x.reserve(points); closed_pieces.y.reserve(points);
  closed_pieces.gx.reserve(points); closed_pieces.gy.reserve(points);
  closed_pieces.offset.reserve(piece_count + 1); closed_pieces.sign_class.reserve(piece_count);
  closed_scratch.Reserve(piece_count, w, h);
  closed_fits.reserve(points / kClosedMinPoints + 1);
}



Status Detector::Impl::PixelStageAt(const ImageView& image) {
  const auto t0 = Clock::now();
  Resize(image.width, image.height);
  const int w = width, h = height;
  const KernelTable& k = *kernels;

  // A noisy frame is smoothed more before the edges (Options::denoise_min_sigma), here on the
  // CPU for every backend, so that all of them see the same bytes. The smoothed frame lives in
  // `nms`, which nothing reads or writes before the edge stage's own smoothing and Sobel are done
  // with it (the Vulkan stage uploads it first).
  ImageView input = image;
  double noise = 0;
  int passes = 0;
  if (options.denoise_min_sigma > 0) {
    noise = scalar::NoiseSigma(image.data, image.stride, w, h);
    passes = noise >= 1.5 * options.denoise_min_sigma ? 2 : noise >= options.denoise_min_sigma ? 1 : 0;
  }
  if (passes == 1) k.gaussian(image.data, image.stride, w, h, nms.data(), w);
  if (passes == 2) {
    k.gaussian(image.data, image.stride, w, h, blurred.data(), w);
    k.gaussian(blurred.data(), w, w, h, nms.data(), w);
  }
  if (passes > 0) input = ImageView{nms.data(), w, h, w};

  // Edges (sec. II-A): on the Vulkan device, or with the CPU kernel table.
  Backend ran = k.backend;
#ifdef ELLIPSEKIT_HAVE_VULKAN
  if (vulkan) {
    const Status st = vulkan->Run(input, options, dx.data(), dy.data(), edge_map.data());
    if (!st.ok()) return st;
    ran = Backend::kVulkan;
  } else
#endif
  {
    const std::uint8_t* src = input.data;
    std::ptrdiff_t src_stride = input.stride;
    if (options.gaussian_blur) {
      k.gaussian(input.data, input.stride, w, h, blurred.data(), w);
      src = blurred.data();
      src_stride = w;
    }
    k.sobel(src, src_stride, w, h, dx.data(), dy.data(), mag.data(), w);
    k.magnitude_histogram(mag.data(), w, h, w, tiles.shift, hist.data(), tiles.tile_max.data());
    SelectThresholds(hist.data(), options, &tiles);
    k.nms(dx.data(), dy.data(), mag.data(), w, h, w, tiles.view(), nms.data(), w);
    k.hysteresis(nms.data(), w, h, w, stack.data());
    k.edge_sign(nms.data(), w, dx.data(), dy.data(), w, w, h, edge_map.data(), w);
  }
  const auto t1 = Clock::now();

  // Curves: 8-connectivity per class, T_n, OBB (sec. II-A); the classes of flat stretches from
  // their shape first (fit/flat_stretches.h; the hysteresis is done with its stack).
  if (options.flat_stretch_classes) {
    ClassifyFlatStretches(edge_map.data(), w, dx.data(), dy.data(), w, w, h, stack.data());
  }
  const int edge_pixels =
      TraceCurves(edge_map.data(), w, dx.data(), dy.data(), w, w, h, options.min_curve_points, &curves, &trace,
                  std::max(options.crowd_min_curve_points, kCrowdTriggerMinPoints), &front.short_curves);
  FilterCurvesByObb(options, &curves, &hull);
  const auto t2 = Clock::now();

  front.ran = ran;
  front.edge_pixels = edge_pixels;
  front.noise_sigma = noise;
  front.denoise_passes = passes;
  front.edges_ms = Ms(t0, t1);
  front.curves_ms = Ms(t1, t2);
  front.arcs_ms = 0;
  front.arcs_capped = false;
  front.arcs_done = false;
  // Arcs (sec. II-B-1, II-B-2) on the device belong to the pixel stage (a stream's worker waits
  // for the device); on the CPU they open the back end, which balances a stream's two threads
  // (generated scenes: edges + curves 0.91 ms, arcs + back end 0.51 ms per frame).
#ifdef ELLIPSEKIT_HAVE_VULKAN
  if (vulkan_arcs) {
    arc_scratch.stats.clear();
    const Status device_arcs = vulkan_arcs->Run(curves, PolylineToleranceQ16(options.polyline_tolerance),
                                                SplitTanQ16(options.split_angle_deg), options.min_curve_points,
                                                &arc_scratch.polylines, &arc_scratch.splits, &arc_scratch.stats);
    // kUnavailable: this frame exceeds the device's buffer range; the CPU table runs it instead.
    if (!device_arcs.ok() && device_arcs.code() != StatusCode::kUnavailable) return device_arcs;
    if (device_arcs.ok()) {
      SelectArcsFromStats(curves, options, &arc_scratch, &arcs, &front.arcs_capped);
      front.arcs_ran = Backend::kVulkan;
      front.arcs_done = true;
      front.arcs_ms = Ms(t2, Clock::now());
    }
  }
#endif
  return Status::Ok();
}

void Detector::Impl::BackEndAt(DetectionResult* r) {
  if (!front.arcs_done) {
    const auto t2 = Clock::now();
    SelectArcs(*kernels, curves, options, &arc_scratch, &arcs, &front.arcs_capped);
    front.arcs_ran = kernels->backend;
    front.arcs_ms = Ms(t2, Clock::now());
  }
  const auto t3 = Clock::now();
  // Grouping, centres, parameters, validation by K and psi (sec. II-B-3 to II-D-2).
  candidates.clear();
  GroupStats gs;
  if (front.arcs_capped) gs.caps_hit |= kCapArcs;
  FindCandidates(curves, arcs, options, &groups, &candidates, &gs);
  const int num_candidates = static_cast<int>(candidates.size());
  const auto t4 = Clock::now();

  // Clustering (sec. II-D-3) of the candidates with edge coverage (our addition,
  // fit/edge_coverage.h), then the outer rims, the exclusive edge support, the stripe test and
  // the refit to the edges (fit/edge_refit.h).
  const CoverageCheck check(EdgeView(), options, &refit_scratch);
  int kept = ClusterCandidates(&candidates, options, &check, &cluster_scratch);
  if (check.BudgetSpent()) gs.caps_hit |= kCapSecondChance;
  CompleteOuterRims(kept, &gs);
  kept = KeepExclusivelySupported(kept);
  kept = DropStriped(kept);
  // The refit, and each detection's score: its support (types.h), the FineEdgeCoverage of the
  // ellipse as reported. The clustering measured its best fit's; still this cluster's ellipse
  // unless a rim or a top over a side replaced it.
  for (int i = 0; i < kept; ++i) {
    Candidate& c = candidates[i];
    double share = SameGeometry(c.ellipse, c.best_fit) ? c.best_fit_share : -1;
    if (options.refit_to_edges) {
      RefitToEdges(EdgeView(), &c.ellipse, &refit_scratch, &share);
    } else if (share < 0) {
      share = FineEdgeCoverage(EdgeView(), c.ellipse);
    }
    c.ellipse.score = share;
  }
  r->ellipses.clear();
  if (r->ellipses.capacity() < candidates.capacity()) r->ellipses.reserve(candidates.capacity());
  for (int i = 0; i < kept; ++i) r->ellipses.push_back(candidates[i].ellipse);
  SortByScore(&r->ellipses);
  const auto t5 = Clock::now();

  r->backend = front.ran;
  r->arc_backend = front.arcs_ran;
  r->simd_target = front.ran == Backend::kSimd ? kernels->simd_target : "";
  r->caps_hit = gs.caps_hit;
  r->num_edge_pixels = front.edge_pixels;
  r->noise_sigma = front.noise_sigma;
  r->denoise_passes = front.denoise_passes;
  r->num_curves = curves.size();
  r->num_arcs = static_cast<int>(arcs.size());
  r->num_pairs = gs.pairs;
  r->num_triplets = gs.triplets;
  r->num_candidates = num_candidates;
  r->timings.edges_ms = front.edges_ms;
  r->timings.curves_ms = front.curves_ms;
  r->timings.arcs_ms = front.arcs_ms;
  r->timings.fit_ms = Ms(t3, t4);
  r->timings.validate_ms = Ms(t4, t5);
  r->timings.total_ms = front.edges_ms + front.curves_ms + front.arcs_ms + Ms(t3, t5);
}

Detector::Detector(const Options& options) : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
  impl_->status = ValidateOptions(options);
  if (impl_->status.ok()) {
    impl_->status = ResolveKernels(options, &impl_->kernels, &impl_->backend_note);
  }
#ifdef ELLIPSEKIT_HAVE_VULKAN
  if (impl_->status.ok() && options.backend == Backend::kVulkan) {
    impl_->status = VulkanEdgeStage::Create(&impl_->vulkan);
    // The arc stage follows it onto the same device (sharing its context: one instance and device
    // per Detector) when the device has shaderInt64; otherwise (the reason is
    // VulkanArcStage::Create's status) the arcs stay on the CPU table.
    if (impl_->status.ok()) {
      const Status arcs = VulkanArcStage::Create(&impl_->vulkan_arcs, impl_->vulkan->context());
      if (!arcs.ok()) {
        impl_->vulkan_arcs.reset();
        std::string& note = impl_->backend_note;
        note += (note.empty() ? "" : "; ") + arcs.message() + "; the arc stage runs on the CPU kernels (" +
                BackendName(impl_->kernels->backend) + ")";
      }
    }
  }
#endif
}

Detector::~Detector() = default;
Detector::Detector(Detector&&) noexcept = default;
Detector& Detector::operator=(Detector&&) noexcept = default;

namespace {
Status MovedFrom() { return {StatusCode::kInvalidArgument, "this Detector was moved from; create a new one"}; }
}  // namespace

Status Detector::status() const { return impl_ ? impl_->status : MovedFrom(); }

const std::string& Detector::backend_note() const {
  static const std::string kNone;
  return impl_ ? impl_->backend_note : kNone;
}

const Options& Detector::options() const {
  static const Options kDefaults;
  return impl_ ? impl_->options : kDefaults;
}

const char* CapName(CapFlags cap) {
  switch (cap) {
    case kCapArcs: return "max_arcs";
    case kCapPairs: return "max_pairs";
    case kCapTriplets: return "max_triplets";
    case kCapCandidates: return "max_candidates";
    case kCapMeanShift: return "max_mean_shift_iterations";
    case kCapRimSearch: return "rim_search_budget";
    case kCapSecondChance: return "second_chance_budget";
    default: return "";
  }
}

Status Detector::detect(const ImageView& image, DetectionResult* result) {
  if (result == nullptr) return Invalid("result is null");
  if (!impl_) return MovedFrom();
  if (!impl_->status.ok()) return impl_->status;
  Status st = ValidateImage(image, impl_->options);
  if (!st.ok()) return st;
  try {
    return impl_->Detect(image, result);
  } catch (const std::exception& e) {  // allocation failure on a first frame; nothing else throws
    return {StatusCode::kInternal, std::string("detect failed: ") + e.what()};
  }
}

}  // namespace ellipsekit
