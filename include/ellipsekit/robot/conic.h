// Ellipses as conics, and the exact image of a 3-D circle.
//
// A conic is a symmetric 3x3 matrix C with p^T C p = 0 for the homogeneous points p = (x, y, 1) on
// the curve. Ellipse parameters follow ellipsekit::Ellipse (pixels, a >= b, theta = OpenCV
// RotatedRect angle in radians, in [-pi/2, pi/2), x right y down, pixel centres at integers).
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "ellipsekit/robot/messages.h"
#include "ellipsekit/types.h"

namespace ellipsekit::robot {

// Conic of an ellipse, normalised to unit Frobenius norm, negative inside (p^T C p < 0 at the centre).
// Fails on non-finite values or a semi-axis <= 0.
Result<Eigen::Matrix3d> EllipseToConic(const Ellipse& e);

// Ellipse parameters of a real, non-degenerate ellipse conic (any scale or sign). Fails for a
// hyperbola, parabola, imaginary or degenerate conic.
Result<Ellipse> ConicToEllipse(const Eigen::Matrix3d& conic);

// Least-squares conic through >= 5 points (normalised for conditioning; the smallest right
// singular vector of the design matrix). Used to carry an ellipse through lens distortion.
Result<Eigen::Matrix3d> FitConic(const std::vector<Eigen::Vector2d>& points);
// The same for exactly kConicSamples points in fixed-size storage: no allocation (the circle pose
// carries a detection through lens distortion this way on every frame).
inline constexpr int kConicSamples = 64;
Result<Eigen::Matrix3d> FitConic(const std::array<Eigen::Vector2d, kConicSamples>& points);

// Point on the ellipse at parameter t (radians): centre + a cos t u + b sin t v.
Eigen::Vector2d EllipsePoint(const Ellipse& e, double t);

// The exact image (in undistorted pixels) of the circle of radius r (metres) centred at
// `centre` with unit normal `normal`, both in the camera optical frame, under intrinsics K:
// plane homography H = K [r u, r v, centre], conic = H^-T diag(1, 1, -1) H^-1.
// Fails when the circle is behind the camera or its image is not an ellipse.
Result<Ellipse> ProjectCircle(const Eigen::Matrix3d& K, const Eigen::Vector3d& centre,
                              const Eigen::Vector3d& normal, double radius);

}  // namespace ellipsekit::robot
