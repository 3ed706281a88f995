// Small closed outlines, our addition (Options::crowd_closed_min_support, closed_min_support): a
// ring of a calibration target, a cap or a top with a semi-minor axis under ~10 px traces as pieces
// shorter than T_n: the edge sign classes (sec. II-A) cut its outline into two to four curves of
// 5-14 points, which T_n drops before any arc is made. Where those pieces close around an outline
// their ends touch. This step joins the curves whose ends lie within kClosedLinkGap px of each
// other into groups and fits one ellipse (the direct least-squares fit of conic_refine.h) to all
// the points of each small group that closes (every end of its curves joined to another curve);
// the caller validates each fit against the edges before keeping it. Much cheaper than the back
// end run again on the pieces (arcs, pairs, triplets): one grid of curve ends, one union-find,
// one fit per group.
#pragma once

#include <cstdint>
#include <vector>

#include "ellipsekit/types.h"
#include "kernels/arc_types.h"

namespace ellipsekit {

// Two curves are joined when an end of one lies within this many px (Chebyshev) of an end of the
// other: 1 is 8-adjacency, where the sign class changes along a rim; 3 bridges two missing pixels.
// Measured (default options, `ellipsekit eval`), gap 1 / 2 / 3 / 4: 150 small rings 5538 / 5767 /
// 5844 / 5762 correct (15 / 15 / 16 / 16 false), cups layout 110 / 112 / 109 / 108 false, crowded
// `--clutter` seed 2 41 / 41 / 39 / 39 false; the other crowded sets within 3 detections.
inline constexpr int kClosedLinkGap = 3;
// A group is fitted when its curves hold at least this many points together.
inline constexpr int kClosedMinPoints = 16;

// What the caller asks of a fit before it keeps it (runtime/detector_crowd.cc), besides its
// support and its size (b <= Options::crowd_max_minor_axis): b >= kClosedMinMinorAxis px, the
// edges near it within kClosedMaxRms px of it in the root mean square (fit/edge_refit.h
// RmsDistanceOfEdgesNear, 1.5 px band), and StripedShare <= kClosedMaxStriped (fit/edge_coverage.h).
// Measured in a first version (the first trace's pieces on every frame, groups fitted whether they
// closed or not, support >= 0.95), true / false detections added (`ellipsekit eval`): support alone
// / with the three tests: hard tabletop seed 1 2 / 21 -> 2 / 0, seed 2 0 / 39 -> 0 / 0, capped
// bottles seed 1 10 / 22 -> 9 / 7, seed 2 10 / 48 -> 9 / 13, 150 small rings 1872 / 24 -> 1839 / 2,
// the shared photographs at 1x 1 / 35 -> 1 / 9 (round holes their truth does not list). The false
// fits were blobs of 3-4 px (b), the innermost of a wooden top's growth rings (a stripe), and the
// rounded squares of a checked tablecloth (0.45-0.8 px from their fit; true outlines 0.33-0.45).
// Asking that groups close: rings 1835 -> 1720 added, bottles 7 + 13 -> 3 + 6 false, 27 % fewer
// instructions in the step.
inline constexpr double kClosedMinMinorAxis = 4;
inline constexpr double kClosedMaxRms = 0.45;
inline constexpr double kClosedMaxStriped = 0.15;

struct ClosedOutlineScratch {
  std::vector<std::int32_t> parent;                  // union-find over curves
  std::vector<std::int32_t> cell_start, cell_ends;   // the grid of curve ends (counting sort)
  std::vector<std::int32_t> min_x, min_y, max_x, max_y, points;  // per group root
  std::vector<std::int32_t> next, tail;  // each group's curves, a list from its root
  std::vector<std::int32_t> open_ends;   // per curve, then per group root: ends joined to no other
  // Room for `curves` curves with their ends in a width x height frame: FitClosedOutlines then
  // allocates nothing for as many.
  void Reserve(std::size_t curves, int width, int height);
};

// Appends to *out (after clearing it) one ellipse per group of curves joined end to end whose
// box is at most max_extent px wide and high and whose points number at least kClosedMinPoints
// (score 0; groups that give no ellipse are left out). Work: O(curves + points); no allocation
// once the scratch and *out have grown to a frame's size.
void FitClosedOutlines(const Curves& curves, double max_extent, ClosedOutlineScratch* scratch,
                       std::vector<Ellipse>* out);

}  // namespace ellipsekit
