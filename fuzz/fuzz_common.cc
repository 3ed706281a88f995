// See fuzz_common.h.
#include "fuzz/fuzz_common.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>

namespace ellipsekit::fuzz {

void Fail(const char* what, const Status& st) {
  std::fprintf(stderr, "ellipsekit fuzz: invariant broken: %s (status %d: %s)\n", what, static_cast<int>(st.code()),
               st.message().c_str());
  std::abort();
}

void EditOption(int field, int v, Options* o) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const double d = v / 64.0;  // fractional values for the double fields
  switch (field % 30) {
    case 0: o->gaussian_blur = (v & 1) != 0; break;
    case 1: o->canny_high_permille = v; break;
    case 2:  // the low ratio, and on odd values the tile (0, 32 .. 256; kernels/canny_thresholds.h)
      o->canny_low_permille = v;
      if (v & 1) o->canny_tile = (v & 2) ? 0 : 32 << ((v >> 2) & 3);
      break;
    case 3:  // the floor, and on odd values the contrast it follows (kernels/canny_thresholds.h)
      o->canny_min_high = v;
      if (v & 1) o->canny_contrast_ref = v / 2;
      break;
    case 4: o->min_curve_points = v; break;
    case 5: o->obb_rule = (v & 1) ? ObbRule::kSideRatio : ObbRule::kMinSide; o->obb_threshold = d; break;
    case 6: o->polyline_tolerance = d; break;
    case 7: o->split_angle_deg = d; break;
    case 8: o->center_method = (v & 1) ? CenterMethod::kArcChords : CenterMethod::kLongestChords; break;
    case 9: o->center_distance = d; break;
    case 10: o->mean_shift_bandwidth = d; break;
    case 11: o->distance_ratio = d; break;
    case 12: o->length_ratio = d; break;
    case 13: o->inlier_rule = (v & 1) ? InlierRule::kAlgebraic : InlierRule::kPixel; o->inlier_threshold = d; break;
    case 14: o->circumference_ratio = v / 1000.0; break;
    case 15: o->cluster_rule = (v & 1) ? ClusterRule::kRelative : ClusterRule::kFeatureDistance; break;
    case 16: o->cluster_distance = d; break;
    case 17: o->cluster_relative = v / 1000.0; break;
    case 18: o->cluster_outer_margin = d; break;
    case 19: o->refine_fit = (v & 1) != 0; o->refined_circumference_ratio = (v >> 1) / 1000.0; break;
    case 20: o->max_arcs = v; break;
    case 21: o->max_pairs = v; break;
    case 22: o->max_triplets = v; break;
    case 23: o->max_candidates = v; break;
    case 24: o->max_mean_shift_iterations = v; break;
    case 25: o->max_image_pixels = v; break;
    case 26: {  // a non-finite value into one of the double fields
      double* fields[] = {&o->obb_threshold, &o->polyline_tolerance, &o->split_angle_deg, &o->center_distance,
                          &o->mean_shift_bandwidth, &o->distance_ratio, &o->length_ratio, &o->inlier_threshold,
                          &o->circumference_ratio, &o->cluster_distance, &o->cluster_outer_margin};
      *fields[static_cast<unsigned>(v) % 11] = (v & 0x100) ? inf : ((v & 0x200) ? -inf : nan);
      break;
    }
    case 27: o->backend = static_cast<Backend>(v); break;  // out-of-range enumerators too
    case 28: o->obb_rule = static_cast<ObbRule>(v & 3); break;
    default: o->center_method = static_cast<CenterMethod>(v & 3); break;
  }
}

void EditOptionMore(int field, int v, Options* o) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const double p = v / 1000.0;  // the share fields live in [0, 1]; v spans [-32.8, 32.8]
  switch (field % 15) {
    case 11: o->crowd_min_curve_points = v; o->crowd_min_short_curves = v >> 4; break;  // < 3 refused
    case 12:
      o->crowd_min_small_found = v;
      o->crowd_min_similar = v >> 4;
      o->crowd_max_minor_axis = v / 16.0;
      if (v & 1) o->closed_min_support = p;  // < 0 refused, [0, 1] on, > 1 off
      if (v & 2) o->crowd_closed_min_support = p;
      break;
    case 9: o->pair_reach = v / 64.0; break;  // <= 0 is refused; large values reach every arc
    case 10: o->retire_found_arcs = (v & 1) != 0; o->fit_pair_centers = (v & 2) != 0; break;
    case 0: o->pair_candidates = (v & 1) != 0; o->pair_min_edge_coverage = (v >> 1) / 1000.0; break;
    case 1: o->min_edge_coverage = p; break;
    case 2: o->min_exclusive_coverage = p; break;
    case 3: o->min_axis_ratio = p; break;
    case 4: o->rim_min_coverage = p; break;  // > 1 turns the outer-rim search off
    case 5:
      o->cluster_pick_best_fit = (v & 1) != 0;
      o->refit_to_edges = (v & 2) != 0;
      o->cluster_recessed_rims = (v & 4) != 0;
      break;
    case 6: o->refined_circumference_ratio = p; break;
    case 7: o->cluster_rule = static_cast<ClusterRule>(v & 3); break;
    case 8: o->inlier_rule = static_cast<InlierRule>(v & 3); break;
    case 13: o->rescue_min_coverage = p; break;  // > 1 turns the second chance off
    default: {  // a non-finite value into one of the double fields above
      double* fields[] = {&o->pair_min_edge_coverage, &o->min_edge_coverage, &o->min_exclusive_coverage,
                          &o->min_axis_ratio, &o->rim_min_coverage, &o->refined_circumference_ratio,
                          &o->cluster_relative, &o->pair_reach, &o->crowd_max_minor_axis, &o->rescue_min_coverage,
                          &o->closed_min_support, &o->crowd_closed_min_support};
      *fields[static_cast<unsigned>(v) % 12] = (v & 0x100) ? inf : ((v & 0x200) ? -inf : nan);
      break;
    }
  }
}

ImageView FuzzView(const std::uint8_t* pixels, const std::uint8_t* never_read, bool null_data, bool sane_geometry,
                   int w, int h, std::ptrdiff_t stride) {
  ImageView view;
  view.data = null_data ? nullptr : (sane_geometry ? pixels : never_read);
  view.width = w;
  view.height = h;
  view.stride = stride;
  return view;
}

void CheckResult(const DetectionResult& r, int w, int h, const Options& o) {
  const Status none;
  if (r.num_edge_pixels < 0 || static_cast<long long>(r.num_edge_pixels) > static_cast<long long>(w) * h)
    Fail("num_edge_pixels out of [0, w*h]", none);
  if (r.num_curves < 0 || r.num_arcs < 0 || r.num_pairs < 0 || r.num_triplets < 0 || r.num_candidates < 0)
    Fail("negative count", none);
  if (r.num_arcs > o.max_arcs) Fail("num_arcs above max_arcs", none);
  // Options::max_pairs: a quarter of it per kind of pair, four consecutive kinds and (with
  // pair_candidates) two opposite ones, at least one pair per kind. The counts hold both passes
  // at the working level (the crowd pass, Options::crowd_min_curve_points), each within the caps.
  const long long passes = 2;
  if (r.num_pairs > passes * 6LL * std::max(1, o.max_pairs / 4)) Fail("num_pairs above max_pairs", none);
  if (r.num_triplets > passes * o.max_triplets) Fail("num_triplets above max_triplets", none);
  if (r.num_candidates > passes * o.max_candidates) Fail("num_candidates above max_candidates", none);
  if (r.ellipses.size() > static_cast<std::size_t>(r.num_candidates)) Fail("more ellipses than candidates", none);
  unsigned known = 0;
  for (CapFlags cap : kAllCaps) known |= cap;
  if (r.caps_hit & ~known) Fail("unknown cap flag", none);
  for (const Ellipse& e : r.ellipses) {
    if (!std::isfinite(e.cx) || !std::isfinite(e.cy) || !std::isfinite(e.a) || !std::isfinite(e.b) ||
        !std::isfinite(e.theta) || !std::isfinite(e.score))
      Fail("non-finite ellipse field", none);
    if (!(e.b > 0) || e.a < e.b) Fail("ellipse axes not a >= b > 0", none);
    if (e.theta < -M_PI / 2 - 1e-9 || e.theta >= M_PI / 2 + 1e-9) Fail("theta outside [-pi/2, pi/2)", none);
  }
  const StageTimings& t = r.timings;
  if (!(t.total_ms >= 0) || !(t.edges_ms >= 0)) Fail("negative timing", none);
}

void CheckSameAsReference(const DetectionResult& reference, const DetectionResult& got) {
  const Status none;
  if (got.num_edge_pixels != reference.num_edge_pixels) Fail("edge pixel count differs from scalar", none);
  if (got.num_curves != reference.num_curves) Fail("curve count differs from scalar", none);
  if (got.num_arcs != reference.num_arcs) Fail("arc count differs from scalar", none);
  if (got.ellipses.size() != reference.ellipses.size()) Fail("ellipse count differs from scalar", none);
  for (std::size_t i = 0; i < got.ellipses.size(); ++i) {
    if (std::memcmp(&got.ellipses[i], &reference.ellipses[i], sizeof(Ellipse)) != 0)
      Fail("ellipse differs from scalar", none);
  }
}

}  // namespace ellipsekit::fuzz
