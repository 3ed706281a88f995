// The fit back end's view of an arc: kernel statistics turned into geometry (doubles).
#pragma once

#include <Eigen/Core>

#include "ellipsekit/types.h"
#include "fit/point_moments.h"
#include "kernels/arc_types.h"

namespace ellipsekit {

struct Arc {
  // Zero until set (Eigen leaves a default-constructed vector uninitialized).
  Eigen::Vector2d p0 = Eigen::Vector2d::Zero(), p1 = Eigen::Vector2d::Zero(), mid = Eigen::Vector2d::Zero();  // end points and middle point, px
  Eigen::Vector2d n0 = Eigen::Vector2d::Zero(), n1 = Eigen::Vector2d::Zero();  // unit gradient (edge normal) at the two ends
  double width = 0, height = 0; // axis-aligned bounding box extents m_i, n_i (eq. 13), px
  int min_x = 0, min_y = 0, max_x = 0, max_y = 0;
  int quadrant = 0;             // Quadrant
  int begin = 0, end = 0;       // point range in Curves, inclusive
  PointMoments moments;         // of the points [begin, end], about the bounding-box centre
  int points() const { return end - begin + 1; }
};

Arc ArcFromStats(const ArcStats& s, const Curves& curves);

// Sets arc->moments from its points; needs begin, end and the bounding box.
void SetArcMoments(const Curves& curves, Arc* arc);

// A validated ellipse and the arc group it came from (indices into the frame's arcs).
struct Candidate {
  Ellipse ellipse;
  int arcs[3] = {-1, -1, -1};  // arc indices; the third is -1 for a pair
  // Set by ClusterCandidates on a cluster reference: the outer rim chosen for it, if any (its
  // ellipse from then on); CompleteOuterRims sets them too when it finds the rim.
  bool has_rim = false;
  bool rim_recessed = false;  // the rim is a recessed lid's (fit/recessed_rim.h), not concentric
  Ellipse rim;
  // Set by ClusterCandidates on a cluster reference: the member with the best FitShare so far
  // (the share -1 until a first member is tried: a lone reference is never measured), and how
  // many members were tried.
  Ellipse best_fit;
  double best_fit_share = -1;
  int fit_tries = 0;

  // A triplet that passed T_c only by its pairs' own fits (Options::fit_pair_centers).
  bool centres_by_fit = false;

  // Passed the clustering's check only once refitted to the edges along its outline
  // (CandidateCheck::PassesRefitted, Options::rescue_min_coverage).
  bool rescued = false;

  bool FromPair() const { return arcs[2] < 0; }  // a two-arc group (Options::pair_candidates)
};

}  // namespace ellipsekit
