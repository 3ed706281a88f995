// Pinhole camera with plumb_bob (Brown–Conrady) distortion, built from a CameraInfo.
//
// Frames and units: 3-D points in the camera optical frame (x right, y down, z forward, metres);
// pixels with centres at integer coordinates, x right, y down. "Normalised" coordinates are
// (X/Z, Y/Z) of an undistorted point. Distortion acts on normalised coordinates:
//   r2 = x^2 + y^2, radial = (1 + k1 r2 + k2 r2^2 + k3 r2^3) / (1 + k4 r2 + k5 r2^2 + k6 r2^3)
//   xd = x radial + 2 t1 x y + t2 (r2 + 2 x^2),  yd = y radial + t1 (r2 + 2 y^2) + 2 t2 x y
// then pixel = K (xd, yd, 1). Undistortion inverts this iteratively (fixed point, as OpenCV).
#pragma once

#include <array>

#include <Eigen/Core>

#include "ellipsekit/robot/messages.h"

namespace ellipsekit::robot {

class CameraModel {
 public:
  CameraModel() = default;

  // Reads K and D of the raw image. Fails on a non-positive focal length, a distortion model
  // other than plumb_bob / rational_polynomial / none, or a D of the wrong length.
  static Result<CameraModel> FromCameraInfo(const CameraInfo& info);

  // The rectified camera (image_proc's image_rect): intrinsics from P, no distortion. Use it when
  // ellipses were detected in the rectified image.
  static Result<CameraModel> RectifiedFromCameraInfo(const CameraInfo& info);

  // Direct construction: fx, fy, cx, cy in pixels; d = k1, k2, t1, t2, k3 (may be shorter, padded
  // with zeros) or 8 rational coefficients.
  static CameraModel FromIntrinsics(double fx, double fy, double cx, double cy,
                                    const std::vector<double>& d = {}, int width = 0, int height = 0);

  double fx() const { return fx_; }
  double fy() const { return fy_; }
  double cx() const { return cx_; }
  double cy() const { return cy_; }
  int width() const { return width_; }
  int height() const { return height_; }
  bool has_distortion() const { return has_distortion_; }
  const std::string& frame_id() const { return frame_id_; }

  // 3x3 intrinsic matrix K (pixels).
  Eigen::Matrix3d K() const;

  // Distorted normalised -> undistorted normalised coordinates (iterative, converges for the
  // distortion of ordinary lenses inside the image).
  Eigen::Vector2d UndistortNormalized(const Eigen::Vector2d& distorted) const;
  // Undistorted normalised -> distorted normalised.
  Eigen::Vector2d DistortNormalized(const Eigen::Vector2d& undistorted) const;

  // Raw pixel -> undistorted normalised coordinates (x/z, y/z).
  Eigen::Vector2d UndistortPixel(const Eigen::Vector2d& pixel) const;
  // Raw pixel -> undistorted pixel of the same camera without distortion (K applied again).
  Eigen::Vector2d UndistortPoint(const Eigen::Vector2d& pixel) const;
  // Raw pixel -> unit ray in the camera optical frame (z > 0).
  Eigen::Vector3d PixelToRay(const Eigen::Vector2d& pixel) const;
  // 3-D point in the camera optical frame (metres, z > 0) -> raw pixel. Fails for z <= 0.
  Result<Eigen::Vector2d> Project(const Eigen::Vector3d& point) const;
  // Undistorted normalised -> raw pixel.
  Eigen::Vector2d NormalizedToPixel(const Eigen::Vector2d& normalized) const;

 private:
  double fx_ = 1, fy_ = 1, cx_ = 0, cy_ = 0;
  std::array<double, 8> d_{};  // k1 k2 t1 t2 k3 k4 k5 k6
  bool has_distortion_ = false;
  int width_ = 0, height_ = 0;
  std::string frame_id_;
};

}  // namespace ellipsekit::robot
