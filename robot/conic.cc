// Ellipse <-> conic conversions and the exact image of a 3-D circle (see conic.h).
#include "ellipsekit/robot/conic.h"

#include <cmath>
#include <numbers>

#include <Eigen/Dense>

namespace ellipsekit::robot {

namespace {

bool Finite(const Ellipse& e) {
  return std::isfinite(e.cx) && std::isfinite(e.cy) && std::isfinite(e.a) && std::isfinite(e.b) &&
         std::isfinite(e.theta);
}

// Angle of an axis direction in [-pi/2, pi/2).
double NormalizeAxisAngle(double t) {
  const double pi = std::numbers::pi;
  t = std::fmod(t, pi);
  if (t < -pi / 2) t += pi;
  if (t >= pi / 2) t -= pi;
  return t;
}

}  // namespace

Result<Eigen::Matrix3d> EllipseToConic(const Ellipse& e) {
  if (!Finite(e) || !(e.a > 0) || !(e.b > 0)) {
    return Result<Eigen::Matrix3d>::Error(StatusCode::kInvalidArgument,
                                          "conic: ellipse has a non-positive or non-finite parameter");
  }
  const double c = std::cos(e.theta), s = std::sin(e.theta);
  Eigen::Matrix2d R;
  R << c, -s, s, c;
  const Eigen::Matrix2d A = R * Eigen::Vector2d(1 / (e.a * e.a), 1 / (e.b * e.b)).asDiagonal() * R.transpose();
  const Eigen::Vector2d x0(e.cx, e.cy);
  Eigen::Matrix3d C;
  C.topLeftCorner<2, 2>() = A;
  C.topRightCorner<2, 1>() = -A * x0;
  C.bottomLeftCorner<1, 2>() = (-A * x0).transpose();
  C(2, 2) = x0.dot(A * x0) - 1;
  return Result<Eigen::Matrix3d>::Ok(C / C.norm());
}

Result<Ellipse> ConicToEllipse(const Eigen::Matrix3d& conic_in) {
  using R = Result<Ellipse>;
  if (!conic_in.allFinite() || conic_in.norm() == 0) {
    return R::Error(StatusCode::kInvalidArgument, "conic: non-finite or zero matrix");
  }
  const Eigen::Matrix3d C = 0.5 * (conic_in + conic_in.transpose()) / conic_in.norm();
  const Eigen::Matrix2d A = C.topLeftCorner<2, 2>();
  const Eigen::Vector2d bv = C.topRightCorner<2, 1>();
  const double det = A.determinant();
  if (!(det > 0)) return R::Error(StatusCode::kInvalidArgument, "conic: not an ellipse");
  const Eigen::Vector2d x0 = -A.ldlt().solve(bv);
  const double f0 = C(2, 2) + bv.dot(x0);  // conic value at the centre
  if (f0 == 0) return R::Error(StatusCode::kInvalidArgument, "conic: degenerate (a point)");
  const Eigen::Matrix2d M = A / (-f0);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(M);
  const Eigen::Vector2d lam = es.eigenvalues();  // ascending
  if (!(lam(0) > 0)) return R::Error(StatusCode::kInvalidArgument, "conic: imaginary ellipse");
  Ellipse e;
  e.cx = x0.x();
  e.cy = x0.y();
  e.a = 1 / std::sqrt(lam(0));
  e.b = 1 / std::sqrt(lam(1));
  const Eigen::Vector2d major = es.eigenvectors().col(0);
  e.theta = NormalizeAxisAngle(std::atan2(major.y(), major.x()));
  return R::Ok(e);
}

namespace {

// FitConic for n points into the design matrix D (n x 6, dynamic or fixed-size storage).
template <class DesignMatrix>
Result<Eigen::Matrix3d> FitConicInto(const Eigen::Vector2d* pts, std::size_t n, DesignMatrix& D) {
  using R = Result<Eigen::Matrix3d>;
  if (n < 5) return R::Error(StatusCode::kInvalidArgument, "conic fit: needs >= 5 points");
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < n; ++i) mean += pts[i];
  mean /= static_cast<double>(n);
  double rms = 0;
  for (std::size_t i = 0; i < n; ++i) rms += (pts[i] - mean).squaredNorm();
  rms = std::sqrt(rms / static_cast<double>(n));
  if (!(rms > 0) || !std::isfinite(rms)) return R::Error(StatusCode::kInvalidArgument, "conic fit: degenerate points");
  const double s = std::sqrt(2.0) / rms;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = (pts[i].x() - mean.x()) * s, y = (pts[i].y() - mean.y()) * s;
    D.row(static_cast<Eigen::Index>(i)) << x * x, x * y, y * y, x, y, 1;
  }
  Eigen::JacobiSVD<DesignMatrix> svd(D, Eigen::ComputeFullV);
  const Eigen::Matrix<double, 6, 1> c = svd.matrixV().col(5);
  Eigen::Matrix3d Cn;
  Cn << c(0), c(1) / 2, c(3) / 2, c(1) / 2, c(2), c(4) / 2, c(3) / 2, c(4) / 2, c(5);
  Eigen::Matrix3d T;  // normalised = T * pixel
  T << s, 0, -s * mean.x(), 0, s, -s * mean.y(), 0, 0, 1;
  const Eigen::Matrix3d C = T.transpose() * Cn * T;
  return R::Ok(C / C.norm());
}

}  // namespace

Result<Eigen::Matrix3d> FitConic(const std::vector<Eigen::Vector2d>& pts) {
  Eigen::MatrixXd D(static_cast<Eigen::Index>(pts.size()), 6);
  return FitConicInto(pts.data(), pts.size(), D);
}

Result<Eigen::Matrix3d> FitConic(const std::array<Eigen::Vector2d, kConicSamples>& pts) {
  Eigen::Matrix<double, kConicSamples, 6> D;
  return FitConicInto(pts.data(), pts.size(), D);
}

Eigen::Vector2d EllipsePoint(const Ellipse& e, double t) {
  const double c = std::cos(e.theta), s = std::sin(e.theta);
  const double u = e.a * std::cos(t), v = e.b * std::sin(t);
  return {e.cx + c * u - s * v, e.cy + s * u + c * v};
}

Result<Ellipse> ProjectCircle(const Eigen::Matrix3d& K, const Eigen::Vector3d& centre,
                              const Eigen::Vector3d& normal_in, double radius) {
  using R = Result<Ellipse>;
  if (!(radius > 0) || !centre.allFinite() || !normal_in.allFinite() || normal_in.norm() == 0) {
    return R::Error(StatusCode::kInvalidArgument, "project circle: bad radius, centre or normal");
  }
  const Eigen::Vector3d n = normal_in.normalized();
  // Lowest z on the circle: centre.z - r * |n x z|.
  if (!(centre.z() - radius * std::sqrt(std::max(0.0, 1 - n.z() * n.z())) > 0)) {
    return R::Error(StatusCode::kInvalidArgument, "project circle: circle not in front of the camera");
  }
  const Eigen::Vector3d helper = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d u = n.cross(helper).normalized();
  const Eigen::Vector3d v = n.cross(u);
  Eigen::Matrix3d H;
  H.col(0) = K * (radius * u);
  H.col(1) = K * (radius * v);
  H.col(2) = K * centre;
  const Eigen::Matrix3d Hi = H.inverse();
  const Eigen::Matrix3d C = Hi.transpose() * Eigen::Vector3d(1, 1, -1).asDiagonal() * Hi;
  return ConicToEllipse(C);
}

}  // namespace ellipsekit::robot
