#include "runtime/coverage_check.h"

#include <algorithm>

#include "fit/edge_coverage.h"
#include "fit/grouping.h"

namespace ellipsekit {

CoverageCheck::CoverageCheck(const EdgeMapView& view, const Options& options, EdgeRefitScratch* scratch)
    : view_(view), options_(options), scratch_(scratch), budget_(2L * view.width * view.height) {}

bool CoverageCheck::Passes(const Candidate& c) const {
  double min_share;
  return MinShare(c.ellipse, c, &min_share) && EdgeCoverage(view_, c.ellipse, min_share) >= min_share;
}

double CoverageCheck::FitShare(const Candidate& c, double to_beat) const {
  return FineEdgeCoverage(view_, c.ellipse, to_beat);
}

bool CoverageCheck::PassesRefitted(Candidate* c) const {
  const double floor = options_.rescue_min_coverage;
  if (!(floor <= 1) || budget_ <= 0 || EdgeCoverage(view_, c->ellipse, floor) < floor) return false;
  Ellipse refit = c->ellipse;
  long scanned = 0;
  const bool refitted = RefitAlongOutline(view_, scratch_, &refit, &scanned);
  budget_ -= scanned;  // charged whether or not the refit holds
  if (!refitted || refit.b < options_.min_axis_ratio * refit.a) return false;
  double min_share;
  if (!MinShare(refit, *c, &min_share) || EdgeCoverage(view_, refit, min_share) < min_share) return false;
  c->ellipse = refit;
  return true;
}

bool CoverageCheck::MinShare(const Ellipse& e, const Candidate& c, double* min_share) const {
  *min_share = c.FromPair() ? options_.pair_min_edge_coverage : options_.min_edge_coverage;
  if (*min_share <= 0) return true;
  if (c.centres_by_fit) *min_share = std::max(*min_share, kCentresByFitMinEdgeCoverage);
  if (options_.frame_cut_min_inside < 1) {
    const double inside = InFrameShare(view_, e);
    if (inside < 1) {
      if (inside < options_.frame_cut_min_inside) return false;
      *min_share *= inside;
    }
  }
  return true;
}

}  // namespace ellipsekit
