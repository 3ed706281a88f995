// Pinhole + plumb_bob / rational_polynomial camera model (see camera_model.h for the math).
#include "ellipsekit/robot/camera_model.h"

#include <algorithm>
#include <cmath>

namespace ellipsekit::robot {

namespace {

Result<CameraModel> Build(double fx, double fy, double cx, double cy, const CameraInfo& info,
                          bool use_distortion) {
  if (!(std::isfinite(fx) && std::isfinite(fy) && fx > 0 && fy > 0 && std::isfinite(cx) &&
        std::isfinite(cy))) {
    return Result<CameraModel>::Error(StatusCode::kInvalidArgument,
                                      "camera: focal lengths must be positive and finite");
  }
  std::vector<double> d;
  if (use_distortion) {
    const std::string& m = info.distortion_model;
    if (m == "plumb_bob") {
      if (!info.d.empty() && info.d.size() != 5) {
        return Result<CameraModel>::Error(StatusCode::kInvalidArgument,
                                          "camera: plumb_bob needs 5 distortion coefficients");
      }
    } else if (m == "rational_polynomial") {
      if (!info.d.empty() && info.d.size() != 8) {
        return Result<CameraModel>::Error(StatusCode::kInvalidArgument,
                                          "camera: rational_polynomial needs 8 coefficients");
      }
    } else if (!(m.empty() || m == "none") || !std::all_of(info.d.begin(), info.d.end(), [](double v) { return v == 0; })) {
      return Result<CameraModel>::Error(StatusCode::kInvalidArgument,
                                        "camera: unsupported distortion model '" + m + "'");
    }
    for (double v : info.d) {
      if (!std::isfinite(v)) {
        return Result<CameraModel>::Error(StatusCode::kInvalidArgument,
                                          "camera: non-finite distortion coefficient");
      }
    }
    if (m == "plumb_bob" || m == "rational_polynomial") d = info.d;
  }
  CameraModel cam = CameraModel::FromIntrinsics(fx, fy, cx, cy, d, static_cast<int>(info.width),
                                                static_cast<int>(info.height));
  return Result<CameraModel>::Ok(cam);
}

}  // namespace

Result<CameraModel> CameraModel::FromCameraInfo(const CameraInfo& info) {
  auto r = Build(info.k[0], info.k[4], info.k[2], info.k[5], info, true);
  if (r.ok()) r.value.frame_id_ = info.header.frame_id;
  return r;
}

Result<CameraModel> CameraModel::RectifiedFromCameraInfo(const CameraInfo& info) {
  auto r = Build(info.p[0], info.p[5], info.p[2], info.p[6], info, false);
  if (r.ok()) r.value.frame_id_ = info.header.frame_id;
  return r;
}

CameraModel CameraModel::FromIntrinsics(double fx, double fy, double cx, double cy,
                                        const std::vector<double>& d, int width, int height) {
  CameraModel c;
  c.fx_ = fx;
  c.fy_ = fy;
  c.cx_ = cx;
  c.cy_ = cy;
  c.width_ = width;
  c.height_ = height;
  for (std::size_t i = 0; i < d.size() && i < c.d_.size(); ++i) c.d_[i] = d[i];
  c.has_distortion_ = false;
  for (double v : c.d_) c.has_distortion_ = c.has_distortion_ || v != 0;
  return c;
}

Eigen::Matrix3d CameraModel::K() const {
  Eigen::Matrix3d k;
  k << fx_, 0, cx_, 0, fy_, cy_, 0, 0, 1;
  return k;
}

Eigen::Vector2d CameraModel::DistortNormalized(const Eigen::Vector2d& u) const {
  if (!has_distortion_) return u;
  const double x = u.x(), y = u.y();
  const double r2 = x * x + y * y;
  const double k1 = d_[0], k2 = d_[1], t1 = d_[2], t2 = d_[3], k3 = d_[4], k4 = d_[5], k5 = d_[6],
               k6 = d_[7];
  const double num = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const double den = 1 + r2 * (k4 + r2 * (k5 + r2 * k6));
  const double radial = num / den;
  return {x * radial + 2 * t1 * x * y + t2 * (r2 + 2 * x * x),
          y * radial + t1 * (r2 + 2 * y * y) + 2 * t2 * x * y};
}

Eigen::Vector2d CameraModel::UndistortNormalized(const Eigen::Vector2d& dist) const {
  if (!has_distortion_) return dist;
  // Fixed point x = (xd - tangential(x)) / radial(x), as cv::undistortPoints; then a few Newton-like
  // refinements are unnecessary for lens distortions met in practice (20 iterations, tol 1e-12).
  const double k1 = d_[0], k2 = d_[1], t1 = d_[2], t2 = d_[3], k3 = d_[4], k4 = d_[5], k5 = d_[6],
               k6 = d_[7];
  double x = dist.x(), y = dist.y();
  for (int it = 0; it < 50; ++it) {
    const double r2 = x * x + y * y;
    const double num = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
    const double den = 1 + r2 * (k4 + r2 * (k5 + r2 * k6));
    const double inv_radial = den / num;
    const double dx = 2 * t1 * x * y + t2 * (r2 + 2 * x * x);
    const double dy = t1 * (r2 + 2 * y * y) + 2 * t2 * x * y;
    const double nx = (dist.x() - dx) * inv_radial;
    const double ny = (dist.y() - dy) * inv_radial;
    const double step = std::abs(nx - x) + std::abs(ny - y);
    x = nx;
    y = ny;
    if (step < 1e-14) break;
  }
  return {x, y};
}

Eigen::Vector2d CameraModel::UndistortPixel(const Eigen::Vector2d& p) const {
  const Eigen::Vector2d d((p.x() - cx_) / fx_, (p.y() - cy_) / fy_);
  return UndistortNormalized(d);
}

Eigen::Vector2d CameraModel::UndistortPoint(const Eigen::Vector2d& p) const {
  const Eigen::Vector2d n = UndistortPixel(p);
  return {fx_ * n.x() + cx_, fy_ * n.y() + cy_};
}

Eigen::Vector3d CameraModel::PixelToRay(const Eigen::Vector2d& p) const {
  const Eigen::Vector2d n = UndistortPixel(p);
  return Eigen::Vector3d(n.x(), n.y(), 1.0).normalized();
}

Eigen::Vector2d CameraModel::NormalizedToPixel(const Eigen::Vector2d& n) const {
  const Eigen::Vector2d d = DistortNormalized(n);
  return {fx_ * d.x() + cx_, fy_ * d.y() + cy_};
}

Result<Eigen::Vector2d> CameraModel::Project(const Eigen::Vector3d& X) const {
  if (!(X.z() > 0) || !X.allFinite()) {
    return Result<Eigen::Vector2d>::Error(StatusCode::kInvalidArgument,
                                          "camera: point is not in front of the camera");
  }
  return Result<Eigen::Vector2d>::Ok(NormalizedToPixel(Eigen::Vector2d(X.x() / X.z(), X.y() / X.z())));
}

}  // namespace ellipsekit::robot
