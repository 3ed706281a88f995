// Constant-velocity Kalman filter in D dimensions (state: D positions then D velocities),
// driven by timestamps: Predict(dt) uses the white-noise-acceleration model with spectral
// density q (units^2 / s^3) per axis.
#pragma once

#include <Eigen/Core>

namespace ellipsekit::robot {

class ConstantVelocityKalman {
 public:
  // position: initial position (units); position_var: its variance (units^2); velocity_var: the
  // initial velocity variance ((units/s)^2); accel_density: q; measurement_var: R per axis.
  ConstantVelocityKalman(const Eigen::VectorXd& position, double position_var, double velocity_var,
                         double accel_density, double measurement_var);

  int dims() const { return static_cast<int>(x_.size() / 2); }
  // Advance by dt seconds (dt <= 0 leaves the state unchanged).
  void Predict(double dt);
  // Fuse a position measurement (D values).
  void Update(const Eigen::VectorXd& z);
  // Squared Mahalanobis distance of a measurement from the predicted position.
  double Mahalanobis2(const Eigen::VectorXd& z) const;

  Eigen::VectorXd position() const { return x_.head(dims()); }
  Eigen::VectorXd velocity() const { return x_.tail(dims()); }
  // The position after a further dt, without changing the filter.
  Eigen::VectorXd PredictedPosition(double dt) const { return position() + dt * velocity(); }
  const Eigen::VectorXd& state() const { return x_; }
  const Eigen::MatrixXd& covariance() const { return P_; }
  Eigen::MatrixXd PositionCovariance() const { return P_.topLeftCorner(dims(), dims()); }

 private:
  Eigen::VectorXd x_;
  Eigen::MatrixXd P_;
  double q_;
  double r_;
};

}  // namespace ellipsekit::robot
