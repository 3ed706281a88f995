// Remaining ellipse parameters once the centre is known (sec. II-C-3, eqs. 8-12).
//
// Eq. 8 is the conjugate-diameter condition: directions with image slopes q1, q2 are conjugate
// for an ellipse of orientation rho (K = tan rho) and axis ratio N = B/A iff
//   (q1 - K)(q2 - K) / ((1 + q1 K)(1 + q2 K)) = -N^2.
// The tangent at an edge point and the line from the centre to that point are such a pair, and
// the edge normal gives the tangent. Written for the centred conic x^T M x = 1 the condition is
// t^T M r = 0, linear in M's three entries, so two pairs (two points) fix M up to scale — the
// same solution eq. 9 gives for K, without slopes that can be infinite. M's eigen-decomposition
// gives rho and N. Each point pair from different arcs votes; the peaks of the two 1-D
// accumulators (densest window: 2 degrees for rho, 0.02 for N) give rho and N. Then every sampled
// point, rotated into the ellipse frame (eqs. 10-11), votes A = sqrt(x_o^2 + y_o^2 / N^2) (eq. 12
// with A_x = A cos rho), whose densest window gives A; B = N A.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "ellipsekit/types.h"
#include "fit/arc.h"

namespace ellipsekit {

struct ParameterScratch {
  std::vector<double> px, py, tx, ty;  // sampled points and unit tangents
  std::vector<int> arc_of;
  std::vector<double> rho, n, a;       // votes
  void Reserve();                      // for the largest group (parameters.cc's sample counts)
};

// arcs: the group's arcs (2 or 3). Returns false when no consistent ellipse comes out.
bool EstimateParameters(const Curves& curves, const Arc* const* arcs, int count,
                        const Eigen::Vector2d& center, ParameterScratch* scratch, Ellipse* out);

// Densest window of `width` over sorted values; returns the mean of the values in it.
// With period > 0 the values live on a circle of that period (they must lie in [0, period)).
double DensestWindowMean(std::vector<double>* values, double width, double period);

// a >= b, theta in [-pi/2, pi/2).
void NormalizeEllipse(Ellipse* e);

}  // namespace ellipsekit
