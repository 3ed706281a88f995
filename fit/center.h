// Ellipse centres from arcs (sec. II-C-1).
//
// Every centre here rests on one property of ellipses: the line through the middle of a chord and
// the pole of that chord (the meeting point of the tangents at its two ends) passes through the
// centre. Tangent lines are built from the edge normal (the Sobel gradient), in homogeneous
// coordinates, so no slope can be infinite and parallel tangents (a diameter, pole at infinity)
// need no special case. This is eqs. 3-7 without the slope form's singularities.
//
//   kLongestChords ("Ours"): of the 6 chords between the 4 end points of an arc pair, the two
//     longest whose centre lines are not near-parallel give the pair centre (Fig. 6(B)); a
//     triplet's centre is the mean shift (flat kernel, Fig. 7) over the intersections of the centre
//     lines of all chords between end points of different arcs, started at the mean of its two
//     pair centres.
//   kArcChords ("Ours^1", refs. [36]-[40]): each arc's own chord gives one centre line (Fig. 6(A));
//     the pair centre is where the two lines meet; a triplet's centre is the mean of its two pair
//     centres.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ellipsekit/options.h"
#include "fit/arc.h"

namespace ellipsekit {

// The line through the chord (p, q)'s middle and its pole, homogeneous (a, b, c): a x + b y + c = 0,
// at no particular scale (IntersectLines does not need one). np, nq are the unit edge normals at p
// and q. Returns false when it is undefined.
bool ChordCenterLine(const Eigen::Vector2d& p, const Eigen::Vector2d& np, const Eigen::Vector2d& q,
                     const Eigen::Vector2d& nq, Eigen::Vector3d* line);

// Where two homogeneous lines (any scale) meet; false when they are (nearly) parallel.
bool IntersectLines(const Eigen::Vector3d& l1, const Eigen::Vector3d& l2, Eigen::Vector2d* point);

bool PairCenter(const Arc& a, const Arc& b, CenterMethod method, Eigen::Vector2d* center);

// *iterations_capped is set when the mean shift stopped at its iteration cap.
Eigen::Vector2d TripletCenter(const Arc& a, const Arc& b, const Arc& c, const Eigen::Vector2d& c_ab,
                              const Eigen::Vector2d& c_bc, const Options& options,
                              bool* iterations_capped);

}  // namespace ellipsekit
