// Refit to the edges, our addition: the last step of a detection. A candidate's ellipse is fitted
// to its group's arcs (two or three of them, conic_refine.h); once the clustering has chosen it,
// the edge map around its whole outline says more: every edge pixel within kEdgeRefitDistance px
// of it whose gradient lies along its normal (fit/edge_coverage.h EdgePointsNear) is fitted again
// by the same direct least-squares fit. Only an ellipse whose outline the edges back closely over
// most of its length (FineEdgeCoverage >= kEdgeRefitMinShare) is refitted: points along a part
// of an outline constrain the rest poorly. The refit replaces the ellipse only when it stays
// close (feature distance, eq. 17, below 0.2 b + 1 px) and the edges back it at least as tightly.
// Measured in README (generated scenes, and circle poses on rendered cans).
#pragma once

#include <cstdint>
#include <vector>

#include "ellipsekit/types.h"
#include "fit/edge_coverage.h"
#include "fit/edge_map_view.h"

namespace ellipsekit {

inline constexpr double kEdgeRefitDistance = 1.5;  // px
inline constexpr double kEdgeRefitMinShare = 0.75;

struct EdgeRefitScratch {
  std::vector<std::int32_t> x, y;
  // Room for the edge pixels near any outline in a width x height frame: its part inside the
  // frame is at most as long as the frame's border, 2 (width + height), and thin (NMS) edges put
  // a few pixels per unit of length into the 5 px band; beyond that room points are left out.
  void Reserve(int width, int height);
};

// Refits *e in place (keeping its score); false when it was left as it was. No allocation once
// scratch is reserved.
// share (optional), in: FineEdgeCoverage(in, *e) when already measured (the clustering's best
// fit), else < 0; out: FineEdgeCoverage(in, *e) of *e as it is on return.
bool RefitToEdges(const EdgeMapView& in, Ellipse* e, EdgeRefitScratch* scratch, double* share = nullptr);

// One step of it, without its checks: *e fitted to the edge pixels within `distance` px of it
// (EdgePointsNear), keeping its score; false (*e left alone) when fewer than 12 are there or they
// give no ellipse. Also the recessed-rim search's step (fit/recessed_rim.h).
bool FitToEdgesNear(const EdgeMapView& in, double distance, EdgeRefitScratch* scratch, Ellipse* e);

// The root mean square of the first-order distances (|F| / |grad F|) to e of the edge pixels
// within `distance` px of it whose gradient lies along its normal (EdgePointsNear); 0 when there are
// none. Thin (NMS) edges along a true ellipse give ~0.33-0.36 px (pixel quantisation); a rounded
// square or a blob of texture that a small ellipse fits within 1 px gives more.
double RmsDistanceOfEdgesNear(const EdgeMapView& in, const Ellipse& e, double distance, EdgeRefitScratch* scratch);

// An ellipse fitted to its group's arcs, refitted to the edges along its whole outline: one
// FitToEdgesNear at kAlongOutlineDistance, kept only when it stays close to *e (feature distance
// below 0.2 b + 1 px, as RefitToEdges); false (*e left alone) otherwise. The clustering's second
// chance for a candidate the edges back too little as fitted (Options::rescue_min_coverage): a fit
// to two arcs of one quadrant pair can be off by a few px on the far side of the outline. Measured
// (correct / detected on hard tabletop seed 1, `ellipsekit eval`), one round at 2 / 2.5 px, two
// rounds at 1.5 px (the second around the first's refit): 715 / 827, 719 / 833, 717 / 828; one
// round at 2.5 px costs ~0.7x two at 1.5 (the band's area). *scanned_pixels grows as in
// FitToEdgesNearRounds (below), also when the refit fails.
inline constexpr double kAlongOutlineDistance = 2.5;  // px
bool RefitAlongOutline(const EdgeMapView& in, EdgeRefitScratch* scratch, Ellipse* e, long* scanned_pixels);

// FitToEdgesNear `rounds` times (the searches around a detection: fit/recessed_rim.h,
// fit/top_over_side.h); false at the first round that fails. *scanned_pixels grows by a bound on
// the pixels each round reads: the outline's length (at most 2 pi max(a, b)) times the band's
// width (2 distance + 2 px), never more than the frame.
bool FitToEdgesNearRounds(const EdgeMapView& in, double distance, int rounds, EdgeRefitScratch* scratch, Ellipse* e,
                          long* scanned_pixels);

// The unit vector along e's minor axis that points up in the image (y down): toward a top's far
// arc when the camera looks down on it.
void MinorAxisUp(const Ellipse& e, double* ux, double* uy);

// How far e's centre lies above ref's along ref's MinorAxisUp, px (negative: below): a rim around
// a recessed lid rises above it (fit/recessed_rim.h), a jar's shoulder drops below its lid
// (fit/clustering.h IsLedgeBelow).
double CentreRise(const Ellipse& e, const Ellipse& ref);

}  // namespace ellipsekit
