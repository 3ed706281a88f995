// Conics and the exact image of a circle under a pinhole camera.
//
// A conic is a symmetric 3x3 matrix Q: image point (x, y) lies on it when [x y 1] Q [x y 1]^T = 0.
// Any non-zero scale (and sign) of Q describes the same conic.
#pragma once

#include <opencv2/core.hpp>

#include "ellipsekit/types.h"

namespace ellipsekit::scenes {

// theta wrapped to [-pi/2, pi/2) (an ellipse's axis is a line, so theta and theta + pi are the same).
double NormalizeAxisAngle(double theta);

// Converts a conic to (cx, cy, a, b, theta), a >= b, theta in [-pi/2, pi/2), score = 0.
// Returns false (leaving *out alone) when Q is not a real, non-degenerate ellipse
// (a hyperbola, parabola, imaginary ellipse, point or non-finite input).
// Math: Q = [[M, d], [d^T, f]] with M = [[A, B/2], [B/2, C]]. Centre c solves M c = -d; then
// (p - c)^T M (p - c) = k with k = -(f + d.c). With M's eigenvalues l_small <= l_large (> 0 once the
// sign is fixed so k > 0): a = sqrt(k / l_small), b = sqrt(k / l_large), and the major axis is
// l_small's eigenvector: theta = atan2(-2 M01, M11 - M00) / 2.
bool ConicToEllipse(const cv::Matx33d& q, ellipsekit::Ellipse* out);

// The conic of an ellipse, scaled so that Q(centre) = -1 (inverse of ConicToEllipse).
cv::Matx33d EllipseToConic(const ellipsekit::Ellipse& e);

// Image conic of the circle {centre + radius (cos t u + sin t v)} (u, v orthonormal) for the camera
// x ~ K (R X + t). With H = K [R (r u), R (r v), R centre + t] the circle is H applied to the unit
// circle diag(1, 1, -1), so its image is H^-T diag(1, 1, -1) H^-1.
cv::Matx33d ProjectCircleConic(const cv::Matx33d& K, const cv::Matx33d& R, const cv::Vec3d& t,
                               const cv::Vec3d& centre, const cv::Vec3d& u, const cv::Vec3d& v,
                               double radius);

}  // namespace ellipsekit::scenes
