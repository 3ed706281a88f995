// Clustering of duplicate candidates (sec. II-D-3, eq. 17): candidates ranked by score
// (K(tau) + psi(tau), best first); each joins the first kept ellipse whose feature distance
//   D = sqrt(dcx^2 + dcy^2 + dA^2 + dB^2 + drho^2)      (px, px, px, px, rad; drho wrapped mod pi)
// is below T_s (or, with ClusterRule::kRelative, is within a tolerance relative to its size), or
// else is kept as a new cluster reference. Our addition: a concentric, larger member whose score
// is within cluster_outer_margin of the reference replaces it (see Options).
#pragma once

#include <vector>

#include "ellipsekit/options.h"
#include "ellipsekit/types.h"
#include "fit/arc.h"

namespace ellipsekit {

double FeatureDistance(const Ellipse& v, const Ellipse& w);

// True when v and w are the same ellipse under options.cluster_rule.
bool SameEllipse(const Ellipse& v, const Ellipse& w, const Options& options);

// Sorts `candidates` by score (in place) and moves the cluster references to its front;
// returns how many there are.
int ClusterCandidates(std::vector<Candidate>* candidates, const Options& options);

}  // namespace ellipsekit
