// The clustering's check (fit/clustering.h CandidateCheck) as the detector runs it: edge coverage.
// Private to the library.
//   Passes          Options::min_edge_coverage of the outline backed by the edge map
//                   (pair_min_edge_coverage for a two-arc candidate, at least
//                   kCentresByFitMinEdgeCoverage for a triplet found by its pairs' fits; an outline
//                   cut by the frame held to the share over its part inside, frame_cut_min_inside).
//   FitShare        FineEdgeCoverage: the ranking of a cluster's members.
//   PassesRefitted  the second chance (Options::rescue_min_coverage): a candidate backed along at
//                   least rescue_min_coverage as fitted, refitted to the edges along its outline
//                   (fit/edge_refit.h RefitAlongOutline) and checked again. Within a budget of two
//                   frames' worth of pixels in the refits' bands, as the outer-rim search's
//                   (runtime/detector_checks.cc); once it is spent, no more second chances and
//                   BudgetSpent() (the detector reports kCapSecondChance).
#pragma once

#include "ellipsekit/options.h"
#include "fit/arc.h"
#include "fit/clustering.h"
#include "fit/edge_map_view.h"
#include "fit/edge_refit.h"

namespace ellipsekit {

class CoverageCheck final : public CandidateCheck {
 public:
  // `scratch`: the refits' buffers, reserved for view's frame (EdgeRefitScratch::Reserve).
  CoverageCheck(const EdgeMapView& view, const Options& options, EdgeRefitScratch* scratch);

  bool Passes(const Candidate& c) const override;
  double FitShare(const Candidate& c, double to_beat) const override;
  bool PassesRefitted(Candidate* c) const override;
  bool BudgetSpent() const { return budget_ <= 0; }

 private:
  // The share of e's outline the edges must back for candidate c (e: c's ellipse or its refit);
  // false when e lies too far out of the frame to be checked at all.
  bool MinShare(const Ellipse& e, const Candidate& c, double* min_share) const;

  EdgeMapView view_;
  const Options& options_;
  EdgeRefitScratch* scratch_;
  mutable long budget_;  // pixels the refits' bands may still cover
};

}  // namespace ellipsekit
