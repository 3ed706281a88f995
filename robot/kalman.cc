// Constant-velocity Kalman filter (see kalman.h).
#include "ellipsekit/robot/kalman.h"

#include <Eigen/Dense>

namespace ellipsekit::robot {

ConstantVelocityKalman::ConstantVelocityKalman(const Eigen::VectorXd& position, double position_var,
                                               double velocity_var, double accel_density,
                                               double measurement_var)
    : q_(accel_density), r_(measurement_var) {
  const int d = static_cast<int>(position.size());
  x_ = Eigen::VectorXd::Zero(2 * d);
  x_.head(d) = position;
  P_ = Eigen::MatrixXd::Zero(2 * d, 2 * d);
  P_.topLeftCorner(d, d).diagonal().setConstant(position_var);
  P_.bottomRightCorner(d, d).diagonal().setConstant(velocity_var);
}

void ConstantVelocityKalman::Predict(double dt) {
  if (!(dt > 0)) return;
  const int d = dims();
  Eigen::MatrixXd F = Eigen::MatrixXd::Identity(2 * d, 2 * d);
  F.topRightCorner(d, d).diagonal().setConstant(dt);
  // Discrete white-noise acceleration: q [dt^3/3, dt^2/2; dt^2/2, dt] per axis.
  Eigen::MatrixXd Q = Eigen::MatrixXd::Zero(2 * d, 2 * d);
  Q.topLeftCorner(d, d).diagonal().setConstant(q_ * dt * dt * dt / 3);
  Q.topRightCorner(d, d).diagonal().setConstant(q_ * dt * dt / 2);
  Q.bottomLeftCorner(d, d).diagonal().setConstant(q_ * dt * dt / 2);
  Q.bottomRightCorner(d, d).diagonal().setConstant(q_ * dt);
  x_ = F * x_;
  P_ = F * P_ * F.transpose() + Q;
}

void ConstantVelocityKalman::Update(const Eigen::VectorXd& z) {
  const int d = dims();
  const Eigen::MatrixXd S = P_.topLeftCorner(d, d) + r_ * Eigen::MatrixXd::Identity(d, d);
  const Eigen::MatrixXd PHt = P_.leftCols(d);  // P H^T with H = [I 0]
  const Eigen::MatrixXd Kg = PHt * S.inverse();
  x_ += Kg * (z - x_.head(d));
  P_ -= Kg * PHt.transpose();
  P_ = 0.5 * (P_ + P_.transpose());
}

double ConstantVelocityKalman::Mahalanobis2(const Eigen::VectorXd& z) const {
  const int d = dims();
  const Eigen::MatrixXd S = P_.topLeftCorner(d, d) + r_ * Eigen::MatrixXd::Identity(d, d);
  const Eigen::VectorXd y = z - x_.head(d);
  return y.dot(S.ldlt().solve(y));
}

}  // namespace ellipsekit::robot
