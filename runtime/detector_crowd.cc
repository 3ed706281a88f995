// The crowd pass (Options::crowd_min_curve_points): the back end again, with a shorter T_n, on the
// edges the ellipses found so far leave unexplained, for the small ellipses of a crowded frame
// whose outlines the paper's T_n drops. Measured in docs/crowded-scenes.md. With
// Options::closed_min_support it also runs outside crowds, for small outlines its edges close.
// After it, the small closed outlines joined from its pieces (fit/closed_outlines.h).
#include <algorithm>

#include "fit/arc_selection.h"
#include "fit/closed_outlines.h"
#include "runtime/detector_impl.h"

namespace ellipsekit {

namespace {
// Measured: frames of dots the first pass misses drop 4-30x more short curves than they keep;
// photographs and tabletop scenes at most 2.1x (docs/crowded-scenes.md).
constexpr int kCrowdShortToLong = 4;
// Outside a crowd (Options::closed_min_support) the pass keeps the curves at most this many
// crowd_max_minor_axis wide and high: a quarter of an outline with that semi-minor axis, seen at
// up to 60 degrees, spans at most 2 of them.
constexpr double kClosedMaxCurveExtent = 2.5;
// AddClosedOutlines fits the groups of pieces at most this many crowd_max_minor_axis wide and
// high (a whole outline with that semi-minor axis, seen at up to 60 degrees, spans at most 4).
constexpr double kClosedMaxGroupExtent = 4;

// Appends the curves of `from` to *to.
void AppendCurves(const Curves& from, Curves* to) {
  const std::int32_t base = static_cast<std::int32_t>(to->x.size());
  to->x.insert(to->x.end(), from.x.begin(), from.x.end());
  to->y.insert(to->y.end(), from.y.begin(), from.y.end());
  to->gx.insert(to->gx.end(), from.gx.begin(), from.gx.end());
  to->gy.insert(to->gy.end(), from.gy.begin(), from.gy.end());
  to->sign_class.insert(to->sign_class.end(), from.sign_class.begin(), from.sign_class.end());
  for (int i = 1; i <= from.size(); ++i) to->offset.push_back(base + from.offset[i]);
}
}  // namespace

// Runs after BackEndAt at the working level, before the coarser levels; adds to r->ellipses in
// the working level's coordinates. Bounded like the first pass: the same caps (a cap it reaches
// is reported in r->caps_hit), and it runs only when the first pass reached none. Its pairs,
// triplets and candidates are added to r's counts.
void Detector::Impl::AddCrowdPass(DetectionResult* r) {
  if (options.crowd_min_curve_points >= options.min_curve_points || r->caps_hit != kCapNone) return;
  const bool closed = options.closed_min_support <= 1;  // the pass runs on every frame, for closed outlines
  // A crowd: the first pass found many small ellipses (their neighbours' pieces are worth a second
  // trace, however few of them reach 12 points: the holes of small rings trace as pieces of 5-9),
  // or found little while the trace dropped many short curves, several times more than it kept
  // (dots too small for T_n; texture drops fewer).
  int small = 0;
  for (const Ellipse& e : r->ellipses) small += e.b <= options.crowd_max_minor_axis;
  const bool crowd = small >= options.crowd_min_small_found ||
                     (front.short_curves >= options.crowd_min_short_curves &&
                      front.short_curves >= kCrowdShortToLong * r->num_curves);
  if (!crowd && !closed) return;
  // The support a closed outline joined from this pass's pieces needs (> 1: the outlines are off).
  const double outline_support =
      crowd ? std::min(options.closed_min_support, options.crowd_closed_min_support) : options.closed_min_support;
  const bool outlines = outline_support <= 1;
  // The first pass's ellipses are in r: its curves, arcs and candidates make room for this pass's.
  const int first_min_points = options.min_curve_points;
  options.min_curve_points = options.crowd_min_curve_points;  // T_n of the trace and the arcs
  // Only the edges the first pass's ellipses leave unexplained: this pass looks for new ones, and
  // re-finding those it has would double the pass's cost (crowded frames: most of its work).
  for (const Ellipse& e : r->ellipses) ClaimEdges(EdgeView(), e, &claims);
  // Its short curves, and its curves before any filter, are the pieces AddClosedOutlines joins.
  TraceCurves(edge_map.data(), width, dx.data(), dy.data(), width, width, height, options.min_curve_points, &curves,
              &trace, 0, nullptr, claims.mask.data(), outlines ? &closed_pieces : nullptr, kClosedMinPiecePoints);
  if (outlines) AppendCurves(curves, &closed_pieces);  // a small ring's outline may be in pieces of either length
  claims.Clear();  // the back end's scratch
  // Not a crowd: only curves that fit a small outline (measured: the same correct detections on
  // every set as with every curve, 6 % fewer instructions over the shared photographs).
  if (!crowd) DropCurvesWiderThan(kClosedMaxCurveExtent * options.crowd_max_minor_axis, &curves);
  FilterCurvesByObb(options, &curves, &hull);
  const bool arcs_done = front.arcs_done;
  front.arcs_done = false;  // the device's arcs were the first pass's curves: CPU arcs now, exact alike
  BackEndAt(&crowd_result);
  front.arcs_done = arcs_done;
  options.min_curve_points = first_min_points;
  r->caps_hit |= crowd_result.caps_hit;
  r->num_pairs += crowd_result.num_pairs;  // the grouping's work counts both passes
  r->num_triplets += crowd_result.num_triplets;
  r->num_candidates += crowd_result.num_candidates;

  // A crowd of similar small ellipses: the semi-minor axes of both passes, sorted, count the
  // similar ones of each in O(log n).
  const std::vector<Ellipse>& found = crowd_result.ellipses;
  minor_axes.clear();
  for (const Ellipse& e : r->ellipses) minor_axes.push_back(e.b);
  for (const Ellipse& e : found) minor_axes.push_back(e.b);
  std::sort(minor_axes.begin(), minor_axes.end());
  const std::size_t first_pass = r->ellipses.size();
  for (const Ellipse& e : found) {
    if (!(e.b <= options.crowd_max_minor_axis)) continue;
    const auto similar = std::upper_bound(minor_axes.begin(), minor_axes.end(), 2 * e.b) -
                         std::lower_bound(minor_axes.begin(), minor_axes.end(), 0.5 * e.b) - 1;  // less e itself
    // One of a crowd of similar ones, or (Options::closed_min_support) an outline its edges close.
    if (!(crowd && similar >= options.crowd_min_similar) && !(e.score >= options.closed_min_support)) continue;
    if (!FoundAlready(r->ellipses.data(), first_pass, e)) r->ellipses.push_back(e);
  }
  if (outlines) AddClosedOutlines(outline_support, r);
}

// The end of AddCrowdPass, on the pieces its trace kept: the fits of FitClosedOutlines whose
// support reaches min_support (Options::crowd_closed_min_support in a crowd, closed_min_support)
// are added to r->ellipses. Each fit it checks is a candidate of the crowd pass: counted in
// r->num_candidates, and within what is left of that pass's Options::max_candidates
// (kCapCandidates when that runs out), so every ellipse reported comes from a counted candidate.
// Work: one fit per group of pieces, and per fit checked one refit (a band scan along an outline
// of b <= crowd_max_minor_axis) and a test against each ellipse found.
void Detector::Impl::AddClosedOutlines(double min_support, DetectionResult* r) {
  if (r->caps_hit != kCapNone) return;
  FitClosedOutlines(closed_pieces, kClosedMaxGroupExtent * options.crowd_max_minor_axis, &closed_scratch, &closed_fits);
  auto small = [&](const Ellipse& e) { return e.b >= kClosedMinMinorAxis && e.b <= options.crowd_max_minor_axis; };
  const int budget = options.max_candidates - crowd_result.num_candidates;
  int checked = 0;
  for (Ellipse e : closed_fits) {
    if (!(small(e) && e.b >= options.min_axis_ratio * e.a)) continue;  // before the refit, which costs more
    if (checked == budget) {
      r->caps_hit |= kCapCandidates;
      break;
    }
    ++checked;
    ++r->num_candidates;
    double share = -1;
    RefitToEdges(EdgeView(), &e, &refit_scratch, &share);
    if (!(share >= min_support && small(e))) continue;
    // Found already, or the inner edge of a rim found already: one ellipse per rim, as the first
    // pass keeps the outer rim of a pair it finds (CompleteOuterRims; a cup's lip seen from above).
    if (FoundAlready(r->ellipses.data(), r->ellipses.size(), e, true) ||
        RmsDistanceOfEdgesNear(EdgeView(), e, kEdgeRefitDistance, &refit_scratch) > kClosedMaxRms ||
        StripedShare(EdgeView(), e, kClosedMaxStriped) > kClosedMaxStriped) {
      continue;
    }
    e.score = share;
    r->ellipses.push_back(e);
  }
}

}  // namespace ellipsekit
