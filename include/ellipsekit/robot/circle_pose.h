// Pose of a circle of known radius from its image (one ellipse; no depth needed).
//
// The ellipse and the camera centre define an oblique elliptic cone. Planes that cut it in a
// circle have two possible normals (the "two-fold ambiguity" of the projected-circle problem);
// for each, the radius fixes the distance. With eigen-decomposition of the cone
// Q = V diag(l1, l2, l3) V^T, l1 >= l2 > 0 > l3, the normals are
//   n = V (sqrt(l1 - l2), 0, +-sqrt(l2 - l3)) / sqrt(l1 - l3)
// and the centre lies on the ray through the pole of the plane's vanishing line, Q^-1 n — the
// true projected centre, which differs from the ellipse centre under perspective.
//
// Frames: everything in the camera optical frame (metres); normals point towards the camera.
#pragma once

#include <array>
#include <optional>

#include <Eigen/Core>

#include "ellipsekit/robot/camera_model.h"
#include "ellipsekit/robot/messages.h"
#include "ellipsekit/types.h"

namespace ellipsekit::robot {

struct CirclePose {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // circle centre, camera frame, metres
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ(); // unit normal, towards the camera (n . centre < 0)
  Eigen::Vector2d centre_pixel = Eigen::Vector2d::Zero();  // projection of `centre` (raw pixels)
};

// The ellipse (raw pixels of `camera`) as a cone matrix in undistorted normalised coordinates,
// x^T Q x = 0 for x = (X/Z, Y/Z, 1). With distortion the boundary is sampled, undistorted and refit.
Result<Eigen::Matrix3d> EllipseToNormalizedCone(const Ellipse& ellipse, const CameraModel& camera);

// Both solutions. Fails on a degenerate ellipse (b <= 0, non-finite) or radius <= 0.
Result<std::array<CirclePose, 2>> CirclePoseCandidates(const Ellipse& ellipse, double radius,
                                                       const CameraModel& camera);

// The solution whose normal is closest to `expected_normal` (camera frame, e.g. the table normal
// rotated into the camera; its sign does not matter).
Result<CirclePose> CirclePoseByNormal(const Ellipse& ellipse, double radius, const CameraModel& camera,
                                      const Eigen::Vector3d& expected_normal);

// The solution whose centre depth (z, metres) is closest to a measured depth of the centre.
Result<CirclePose> CirclePoseByDepth(const Ellipse& ellipse, double radius, const CameraModel& camera,
                                     double measured_depth_z);

// The raw pixel where the centre of the circle projects, given only the plane normal (camera
// frame): the pole of the vanishing line n w.r.t. the ellipse. Radius-free.
Result<Eigen::Vector2d> ProjectedCircleCentre(const Ellipse& ellipse, const CameraModel& camera,
                                              const Eigen::Vector3d& plane_normal);

// Orientation (quaternion x, y, z, w) whose z axis is `normal` (camera frame); the x axis is the
// camera x axis made orthogonal to the normal (or camera y if x is parallel).
Quaternion OrientationFromNormal(const Eigen::Vector3d& normal);

}  // namespace ellipsekit::robot
