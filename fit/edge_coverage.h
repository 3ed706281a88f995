// Edge support of an ellipse, our addition: how much of its outline the edge map backs.
// psi (eq. 16) measures how well the group's own arcs fit the ellipse; it cannot see an ellipse
// fitted through arcs of different objects, whose outline elsewhere crosses no edge. A point of
// the outline is supported when a pixel of its 3x3 neighbourhood is an edge pixel whose gradient
// is within ~26.6 degrees of the ellipse normal there (cos^2 >= 0.8, either sign).
//   EdgeCoverage      the outline cut into 64 sectors of equal parametric angle; a sector is
//                     covered when one of its 4 sample points is supported (a detection test).
//   FineEdgeCoverage  the share of 64 sample points (one mid-sector each) supported by an edge
//                     pixel that also lies within 1 px of the ellipse (first-order distance):
//                     which of two close ellipses the edges back more tightly (a ranking, for
//                     the clustering; 64 samples rank as well as 256 on the generated scenes and
//                     shared datasets, +-1 detection, at a quarter of the cost).
//   EdgeClaims        edge pixels already explained by an accepted ellipse: EdgeCoverage can
//                     leave them out, so a second ellipse must stand on edges of its own.
//   StripedShare      whether the outline is one edge or one stripe of a pattern of them (the
//                     growth rings of a wooden top, a grooved or ribbed surface): the share of
//                     its backed samples with opposite-signed edges close on both sides.
#pragma once

#include <cstdint>
#include <vector>

#include "ellipsekit/types.h"
#include "fit/edge_map_view.h"

namespace ellipsekit {

// A frame-sized mask of claimed edge pixels and the list of those set (to clear them cheaply).
struct EdgeClaims {
  std::vector<std::uint8_t> mask;   // width * height, row-major without padding
  std::vector<std::int32_t> claimed;

  void Resize(int width, int height);  // all unclaimed; the only allocation
  void Clear();                        // unclaims what was claimed; O(claimed pixels)
};

// In [0, 1]. Work: at most 256 samples x 9 pixels, whatever the ellipse; samples outside the
// frame do not cover. With min_share > 0 it stops as soon as min_share is out of reach and returns
// the share found so far (then < min_share): the same accept/reject decision, less work.
// With `exclude`, claimed pixels support nothing.
double EdgeCoverage(const EdgeMapView& in, const Ellipse& e, double min_share = 0,
                    const EdgeClaims* exclude = nullptr);

// In [0, 1]: the share of EdgeCoverage's 64 sectors whose middle sample lies inside the frame.
double InFrameShare(const EdgeMapView& in, const Ellipse& e);

// Two ellipses can share an edge pixel only when their outlines lie within EdgeCoverage's 3x3
// window (1.5 px) plus ClaimEdges' 3 px band of each other: bounding boxes each grown by
// kClaimReach px (meeting at 6 px) find every such pair.
inline constexpr double kClaimReach = 3;

// Claims every edge pixel within 3 px of the outline (first-order distance) whose gradient lies
// along the ellipse's normal there: wider than EdgeCoverage's 3x3, so an ellipse a pixel off the
// claimed one finds no support of its own on the same edge. Work: the pixels of a 9 px wide band
// along the outline, empty runs skipped 8 at a time.
void ClaimEdges(const EdgeMapView& in, const Ellipse& e, EdgeClaims* claims);

// In [0, 1]. Stops once `to_beat` is out of reach and returns a value <= to_beat then.
double FineEdgeCoverage(const EdgeMapView& in, const Ellipse& e, double to_beat = -1);

// The edge pixels within `distance` px of e (first-order distance) whose gradient lies along its
// normal there, row by row: into xs, ys, up to their capacity (never allocates; the caller
// reserves, EdgeRefitScratch::Reserve). Work: the pixels of a band 2 distance + 2 px wide.
int EdgePointsNear(const EdgeMapView& in, const Ellipse& e, double distance, std::vector<std::int32_t>* xs,
                   std::vector<std::int32_t>* ys);

// In [0, 1]: of the 64 samples FineEdgeCoverage takes (one mid-sector each) whose gradient along
// the outline's normal, within 1 px, reaches 8 (L1 Sobel units), the share whose gradient along
// that normal turns to the opposite sign, at >= 0.4 of it, both 2-5 px outside and 2-5 px inside
// (a stripe among stripes; a rim, a lip or a ring band has such an edge on one side only). 0 when
// no sample is backed. With to_exceed >= 0 it stops once the share cannot exceed to_exceed and
// returns a value <= to_exceed then (a rim is known after ~10 samples). Work: <= 64 x 11 gradient
// reads.
double StripedShare(const EdgeMapView& in, const Ellipse& e, double to_exceed = -1);

}  // namespace ellipsekit
