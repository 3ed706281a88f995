// Clustering of duplicate candidates (sec. II-D-3, eq. 17): candidates ranked by score
// (K(tau) + psi(tau), best first); each joins the first kept ellipse whose feature distance
//   D = sqrt(dcx^2 + dcy^2 + dA^2 + dB^2 + drho^2)      (px, px, px, px, rad; drho wrapped mod pi)
// is below T_s (or, with ClusterRule::kRelative, is within a tolerance relative to its size), or
// else is kept as a new cluster reference. Our addition: a cluster whose members include the
// reference's outer rim (IsOuterRim) within cluster_outer_margin of its score is represented by
// the best such rim: a can, cup or cap top shows a lip as two nested similar ellipses, and the
// outer one is the object's boundary, which a grasp needs (see Options).
#pragma once

#include <vector>

#include "ellipsekit/options.h"
#include "ellipsekit/types.h"
#include "fit/arc.h"

namespace ellipsekit {

// Nested-rim geometry, our addition: `outer` is concentric with `inner` (centres within
// kRimCentreTolerance * inner.b), larger by a factor (a + b) in [kRimMinScale, kRimMaxScale], and
// of the same shape (b/a within kRimAxisRatioTolerance, orientation within
// kRimOrientationTolerance rad unless both are nearly round).
inline constexpr double kRimCentreTolerance = 0.1;
inline constexpr double kRimMinScale = 1.08;
inline constexpr double kRimMaxScale = 1.45;
inline constexpr double kRimAxisRatioTolerance = 0.05;
inline constexpr double kRimOrientationTolerance = 0.2;
bool IsOuterRim(const Ellipse& outer, const Ellipse& inner);

double FeatureDistance(const Ellipse& v, const Ellipse& w);

// True when v and w are the same ellipse under options.cluster_rule.
bool SameEllipse(const Ellipse& v, const Ellipse& w, const Options& options);

// A check a candidate must pass to found or represent a cluster (the edge coverage), asked lazily:
// only of candidates that would, so duplicates of a cluster are never checked. The result is the
// same as removing every failing candidate first.
class CandidateCheck {
 public:
  virtual bool Passes(const Ellipse& e) const = 0;

 protected:
  ~CandidateCheck() = default;
};

// Sorts `candidates` by score (in place) and moves the cluster references to its front;
// returns how many there are. With `check`, candidates failing it are left out.
int ClusterCandidates(std::vector<Candidate>* candidates, const Options& options,
                      const CandidateCheck* check = nullptr);

}  // namespace ellipsekit
