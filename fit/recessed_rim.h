// The rim of a recessed lid, our addition. A drink can's lid lies a few millimetres below its
// rolled rim: seen from above at an angle, the lid's far edge and the rim's inner wall on the
// near side outline a bright, clean ellipse that the arcs find, while the rim itself, the truth
// and what a grasp needs, is larger, wider along b than along a, and centred higher in the image
// (measured on the hard tabletop set, seed 1: 1.05-1.31x along a, 1.11-1.44x along b, 0-0.27 b
// up; docs/hard-tabletop.md). The concentric outer-rim search (fit/rim_search.h, one scale) cannot
// reach it. FindRecessedRim starts from the median of those (1.17 a, 1.25 b, 0.15 b up), refits
// that guess to the edges near it three times, and accepts the result only when it is such a rim
// and the edges back it tightly.
#pragma once

#include "ellipsekit/types.h"
#include "fit/edge_map_view.h"
#include "fit/edge_refit.h"

namespace ellipsekit {

// Starting guess, from the detected lid: semi-axes scaled by these, centre moved this many b up.
inline constexpr double kRecessedRimA = 1.17;
inline constexpr double kRecessedRimB = 1.25;
inline constexpr double kRecessedRimUp = 0.15;
// A rim accepted: a in [1.03, 1.4] a_lid, b in [1.05, 1.55] b_lid and not relatively narrower
// than the lid (b / b_lid >= a / a_lid - 0.02), centre within 0.35 b up (0.05 b down) and 0.15 b
// across the minor axis, and FineEdgeCoverage >= kRecessedRimMinShare.
inline constexpr double kRecessedRimMinShare = 0.85;
// The geometry above: `rim` is where a recessed lid's rim lies around `lid`.
bool IsRecessedRimOf(const Ellipse& rim, const Ellipse& lid);

// The starting guess must be backed this much (FineEdgeCoverage) before any refit: a cheap test
// that most detections (no recessed lid) fail. Measured (`ellipsekit eval`, correct detections):
// 0 / 0.3 / 0.5 gives hard tabletop seed 1 672 / 670 / 669 (660 without the search), seed 2 686 /
// 685 at 0.3 / 0.5 (680); at 0.3 su2019_coin coin_7 took 5 % longer, at 0.5 no photograph did.
inline constexpr double kRecessedRimGuessShare = 0.5;

// True and *rim set (score kept from lid) when a recessed lid's rim is found around `lid`. Work:
// one FineEdgeCoverage, then at most three scans of a 6 px band along the guess and a fit;
// *scanned_pixels = a bound on the pixels those scans read (the caller's budget). No allocation
// once scratch is reserved.
bool FindRecessedRim(const EdgeMapView& in, const Ellipse& lid, EdgeRefitScratch* scratch, Ellipse* rim,
                     long* scanned_pixels);

}  // namespace ellipsekit
