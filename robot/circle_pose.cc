// Pose of a circle of known radius from one ellipse (see circle_pose.h for the math).
#include "ellipsekit/robot/circle_pose.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "ellipsekit/robot/conic.h"

namespace ellipsekit::robot {

namespace {

bool Degenerate(const Ellipse& e) {
  return !(std::isfinite(e.cx) && std::isfinite(e.cy) && std::isfinite(e.a) && std::isfinite(e.b) &&
           std::isfinite(e.theta) && e.a > 0 && e.b > 0 && e.b <= e.a * (1 + 1e-9));
}

}  // namespace

Result<Eigen::Matrix3d> EllipseToNormalizedCone(const Ellipse& ellipse, const CameraModel& camera) {
  using R = Result<Eigen::Matrix3d>;
  if (Degenerate(ellipse)) return R::Error(StatusCode::kInvalidArgument, "circle pose: degenerate ellipse");
  if (!camera.has_distortion()) {
    auto c = EllipseToConic(ellipse);
    if (!c.ok()) return c;
    const Eigen::Matrix3d K = camera.K();
    const Eigen::Matrix3d Q = K.transpose() * c.value * K;  // pixel = K * normalised
    return R::Ok(Q / Q.norm());
  }
  // Distortion bends the ellipse; sample its boundary, undistort, refit (kConicSamples = 64 points,
  // exact for a conic, and a least-squares conic for the mildly non-conic undistorted curve). Fixed
  // storage: no allocation per call.
  std::array<Eigen::Vector2d, kConicSamples> pts;
  for (int i = 0; i < kConicSamples; ++i) {
    pts[static_cast<std::size_t>(i)] =
        camera.UndistortPixel(EllipsePoint(ellipse, 2 * std::numbers::pi * i / static_cast<double>(kConicSamples)));
  }
  return FitConic(pts);
}

Result<std::array<CirclePose, 2>> CirclePoseCandidates(const Ellipse& ellipse, double radius,
                                                       const CameraModel& camera) {
  using R = Result<std::array<CirclePose, 2>>;
  if (!(radius > 0) || !std::isfinite(radius)) {
    return R::Error(StatusCode::kInvalidArgument, "circle pose: radius must be positive");
  }
  auto cone = EllipseToNormalizedCone(ellipse, camera);
  if (!cone.ok()) return R{cone.status, {}};
  Eigen::Matrix3d Q = cone.value;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(Q);
  Eigen::Vector3d lam = es.eigenvalues();
  Eigen::Matrix3d V = es.eigenvectors();
  int positives = static_cast<int>((lam.array() > 0).count());
  if (positives == 1) {
    Q = -Q;
    lam = -lam;
    positives = 2;
  }
  if (positives != 2 || (lam.array() == 0).any()) {
    return R::Error(StatusCode::kInvalidArgument, "circle pose: ellipse does not define a real cone");
  }
  // Order: l1 >= l2 > 0 > l3.
  int idx[3] = {0, 1, 2};
  std::sort(idx, idx + 3, [&](int i, int j) { return lam(i) > lam(j); });
  const double l1 = lam(idx[0]), l2 = lam(idx[1]), l3 = lam(idx[2]);
  const Eigen::Vector3d e1 = V.col(idx[0]), e3 = V.col(idx[2]);
  const double g = std::sqrt(l1 - l3);
  const double c1 = std::sqrt(std::max(0.0, l1 - l2)) / g;
  const double c3 = std::sqrt(std::max(0.0, l2 - l3)) / g;
  const Eigen::Matrix3d Qi = Q.inverse();

  std::array<CirclePose, 2> out;
  for (int k = 0; k < 2; ++k) {
    Eigen::Vector3d n = (c1 * e1 + (k == 0 ? 1.0 : -1.0) * c3 * e3).normalized();
    const Eigen::Vector3d ray = Qi * n;  // direction of the centre: pole of the vanishing line
    const double nr = n.dot(ray);
    if (!(std::abs(nr) > 1e-15)) return R::Error(StatusCode::kInternal, "circle pose: centre at infinity");
    Eigen::Vector3d x0 = ray / nr;  // centre on the plane n . x = 1
    const Eigen::Vector3d helper = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d u = n.cross(helper).normalized();
    const double rho2 = -x0.dot(Q * x0) / u.dot(Q * u);  // radius^2 of the cut at unit distance
    if (!(rho2 > 0)) return R::Error(StatusCode::kInternal, "circle pose: no real circular section");
    Eigen::Vector3d centre = x0 * (radius / std::sqrt(rho2));
    if (centre.z() < 0) centre = -centre;  // the nappe in front of the camera
    if (n.dot(centre) > 0) n = -n;         // normal towards the camera
    out[k].centre = centre;
    out[k].normal = n;
    out[k].centre_pixel = camera.NormalizedToPixel(Eigen::Vector2d(centre.x() / centre.z(), centre.y() / centre.z()));
  }
  return R::Ok(out);
}

Result<CirclePose> CirclePoseByNormal(const Ellipse& ellipse, double radius, const CameraModel& camera,
                                      const Eigen::Vector3d& expected_normal) {
  using R = Result<CirclePose>;
  if (!expected_normal.allFinite() || expected_normal.norm() == 0) {
    return R::Error(StatusCode::kInvalidArgument, "circle pose: zero expected normal");
  }
  auto c = CirclePoseCandidates(ellipse, radius, camera);
  if (!c.ok()) return R{c.status, {}};
  const Eigen::Vector3d m = expected_normal.normalized();
  const double d0 = std::abs(c.value[0].normal.dot(m)), d1 = std::abs(c.value[1].normal.dot(m));
  return R::Ok(d0 >= d1 ? c.value[0] : c.value[1]);
}

Result<CirclePose> CirclePoseByDepth(const Ellipse& ellipse, double radius, const CameraModel& camera,
                                     double measured_depth_z) {
  using R = Result<CirclePose>;
  if (!(measured_depth_z > 0) || !std::isfinite(measured_depth_z)) {
    return R::Error(StatusCode::kInvalidArgument, "circle pose: measured depth must be positive");
  }
  auto c = CirclePoseCandidates(ellipse, radius, camera);
  if (!c.ok()) return R{c.status, {}};
  const double d0 = std::abs(c.value[0].centre.z() - measured_depth_z);
  const double d1 = std::abs(c.value[1].centre.z() - measured_depth_z);
  return R::Ok(d0 <= d1 ? c.value[0] : c.value[1]);
}

Result<Eigen::Vector2d> ProjectedCircleCentre(const Ellipse& ellipse, const CameraModel& camera,
                                              const Eigen::Vector3d& plane_normal) {
  using R = Result<Eigen::Vector2d>;
  if (!plane_normal.allFinite() || plane_normal.norm() == 0) {
    return R::Error(StatusCode::kInvalidArgument, "projected centre: zero normal");
  }
  auto cone = EllipseToNormalizedCone(ellipse, camera);
  if (!cone.ok()) return R{cone.status, {}};
  const Eigen::Vector3d ray = cone.value.inverse() * plane_normal.normalized();
  if (!(std::abs(ray.z()) > 1e-12 * ray.norm())) {
    return R::Error(StatusCode::kInvalidArgument, "projected centre: centre at infinity");
  }
  return R::Ok(camera.NormalizedToPixel(Eigen::Vector2d(ray.x() / ray.z(), ray.y() / ray.z())));
}

Quaternion OrientationFromNormal(const Eigen::Vector3d& normal) {
  const Eigen::Vector3d z = normal.normalized();
  Eigen::Vector3d x = Eigen::Vector3d::UnitX() - z.x() * z;
  if (x.norm() < 1e-6) x = Eigen::Vector3d::UnitY() - z.y() * z;
  x.normalize();
  Eigen::Matrix3d R;
  R.col(0) = x;
  R.col(1) = z.cross(x);
  R.col(2) = z;
  const Eigen::Quaterniond q(R);
  return Quaternion{q.x(), q.y(), q.z(), q.w()};
}

}  // namespace ellipsekit::robot
