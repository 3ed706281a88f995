// SetOption: one Options field from "name=value" (CLI --option, configuration files).
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>

#include "ellipsekit/detector.h"
#include "ellipsekit/options.h"

namespace ellipsekit {

namespace {

// Parsers leave *v untouched unless the whole text is a valid value.
bool ParseDouble(const std::string& s, double* v) {
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(s.c_str(), &end);
  if (errno != 0 || end != s.c_str() + s.size()) return false;
  *v = x;
  return true;
}

bool ParseInt(const std::string& s, int* v) {
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  const long x = std::strtol(s.c_str(), &end, 10);
  if (errno != 0 || end != s.c_str() + s.size() || x < -2147483647L || x > 2147483647L) return false;
  *v = static_cast<int>(x);
  return true;
}

bool ParseBool(const std::string& s, bool* v) {
  if (s == "true" || s == "1" || s == "on") { *v = true; return true; }
  if (s == "false" || s == "0" || s == "off") { *v = false; return true; }
  return false;
}

}  // namespace

Status SetOption(const std::string& assignment, Options* o) {
  const std::size_t eq = assignment.find('=');
  if (eq == std::string::npos) return {StatusCode::kInvalidArgument, "option '" + assignment + "' is not NAME=VALUE"};
  const std::string name = assignment.substr(0, eq), value = assignment.substr(eq + 1);
  auto bad = [&](const char* expected) {
    return Status(StatusCode::kInvalidArgument, "option " + name + ": bad value '" + value + "', expected " + expected);
  };
  struct DoubleField { const char* name; double Options::*field; };
  struct IntField { const char* name; int Options::*field; };
  static const DoubleField doubles[] = {
      {"obb_threshold", &Options::obb_threshold}, {"polyline_tolerance", &Options::polyline_tolerance},
      {"split_angle_deg", &Options::split_angle_deg}, {"center_distance", &Options::center_distance},
      {"mean_shift_bandwidth", &Options::mean_shift_bandwidth}, {"distance_ratio", &Options::distance_ratio},
      {"length_ratio", &Options::length_ratio}, {"inlier_threshold", &Options::inlier_threshold},
      {"circumference_ratio", &Options::circumference_ratio},
      {"refined_circumference_ratio", &Options::refined_circumference_ratio}, {"cluster_distance", &Options::cluster_distance},
      {"cluster_relative", &Options::cluster_relative},
      {"cluster_outer_margin", &Options::cluster_outer_margin},
      {"rim_min_coverage", &Options::rim_min_coverage},
      {"min_edge_coverage", &Options::min_edge_coverage},
      {"frame_cut_min_inside", &Options::frame_cut_min_inside},
      {"min_exclusive_coverage", &Options::min_exclusive_coverage},
      {"max_striped_share", &Options::max_striped_share},
      {"max_nested_striped_share", &Options::max_nested_striped_share},
      {"pair_min_edge_coverage", &Options::pair_min_edge_coverage},
      {"rescue_min_coverage", &Options::rescue_min_coverage},
      {"closed_min_support", &Options::closed_min_support},
      {"crowd_closed_min_support", &Options::crowd_closed_min_support},
      {"pair_reach", &Options::pair_reach},
      {"crowd_max_minor_axis", &Options::crowd_max_minor_axis},
      {"min_axis_ratio", &Options::min_axis_ratio},
      {"denoise_min_sigma", &Options::denoise_min_sigma},
  };
  static const IntField ints[] = {
      {"canny_high_permille", &Options::canny_high_permille}, {"canny_low_permille", &Options::canny_low_permille},
      {"canny_min_high", &Options::canny_min_high}, {"canny_contrast_ref", &Options::canny_contrast_ref},
      {"canny_tile", &Options::canny_tile},
      {"min_curve_points", &Options::min_curve_points},
      {"max_arcs", &Options::max_arcs}, {"max_pairs", &Options::max_pairs},
      {"max_triplets", &Options::max_triplets}, {"max_candidates", &Options::max_candidates},
      {"max_mean_shift_iterations", &Options::max_mean_shift_iterations},
      {"max_image_pixels", &Options::max_image_pixels}, {"pyramid_level", &Options::pyramid_level},
      {"pyramid_max_pixels", &Options::pyramid_max_pixels}, {"coarse_levels", &Options::coarse_levels},
      {"coarse_min_pixels", &Options::coarse_min_pixels},
      {"crowd_min_curve_points", &Options::crowd_min_curve_points},
      {"crowd_min_short_curves", &Options::crowd_min_short_curves}, {"crowd_min_similar", &Options::crowd_min_similar},
      {"crowd_min_small_found", &Options::crowd_min_small_found},
  };
  for (const DoubleField& f : doubles) {
    if (name == f.name) return ParseDouble(value, &(o->*f.field)) ? Status::Ok() : bad("a number");
  }
  for (const IntField& f : ints) {
    if (name == f.name) return ParseInt(value, &(o->*f.field)) ? Status::Ok() : bad("an integer");
  }
  struct BoolField { const char* name; bool Options::*field; };
  static const BoolField bools[] = {
      {"gaussian_blur", &Options::gaussian_blur}, {"refine_fit", &Options::refine_fit},
      {"pair_candidates", &Options::pair_candidates}, {"cluster_pick_best_fit", &Options::cluster_pick_best_fit},
      {"cluster_recessed_rims", &Options::cluster_recessed_rims},
      {"top_over_side", &Options::top_over_side}, {"lid_inside", &Options::lid_inside},
      {"refit_to_edges", &Options::refit_to_edges}, {"refit_to_image", &Options::refit_to_image}, {"retire_found_arcs", &Options::retire_found_arcs},
      {"fit_pair_centers", &Options::fit_pair_centers}, {"flat_stretch_classes", &Options::flat_stretch_classes},
  };
  for (const BoolField& f : bools) {
    if (name == f.name) return ParseBool(value, &(o->*f.field)) ? Status::Ok() : bad("true or false");
  }
  if (name == "simd_target") {
    o->simd_target = value;  // checked against the available targets when a Detector is created
    return Status::Ok();
  }
  if (name == "backend") return ParseBackend(value.c_str(), &o->backend) ? Status::Ok() : bad("auto, scalar, simd or vulkan");
  if (name == "center_method") {
    if (value == "longest_chords") { o->center_method = CenterMethod::kLongestChords; return Status::Ok(); }
    if (value == "arc_chords") { o->center_method = CenterMethod::kArcChords; return Status::Ok(); }
    return bad("longest_chords or arc_chords");
  }
  if (name == "obb_rule") {
    if (value == "min_side") { o->obb_rule = ObbRule::kMinSide; return Status::Ok(); }
    if (value == "side_ratio") { o->obb_rule = ObbRule::kSideRatio; return Status::Ok(); }
    return bad("min_side or side_ratio");
  }
  if (name == "inlier_rule") {
    if (value == "algebraic") { o->inlier_rule = InlierRule::kAlgebraic; return Status::Ok(); }
    if (value == "pixel") { o->inlier_rule = InlierRule::kPixel; return Status::Ok(); }
    return bad("algebraic or pixel");
  }
  if (name == "cluster_rule") {
    if (value == "feature_distance") { o->cluster_rule = ClusterRule::kFeatureDistance; return Status::Ok(); }
    if (value == "relative") { o->cluster_rule = ClusterRule::kRelative; return Status::Ok(); }
    return bad("feature_distance or relative");
  }
  // Unknown: list every accepted name, so a typo is fixed without opening options.h.
  std::string accepted;
  auto add = [&](const char* n) { accepted += (accepted.empty() ? "" : ", ") + std::string(n); };
  for (const DoubleField& f : doubles) add(f.name);
  for (const IntField& f : ints) add(f.name);
  for (const BoolField& f : bools) add(f.name);
  for (const char* n : {"simd_target", "backend", "center_method", "obb_rule", "inlier_rule", "cluster_rule"}) add(n);
  return {StatusCode::kInvalidArgument, "unknown option '" + name + "'; the options are: " + accepted};
}

}  // namespace ellipsekit
