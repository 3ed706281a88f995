// Constant-velocity Kalman filter in D dimensions (state: D positions then D velocities),
// driven by timestamps: Predict(dt) uses the white-noise-acceleration model with spectral
// density q (units^2 / s^3) per axis.
//
// D is 1..3 (an image centre: 2, a 3-D point: 3). The state and covariance live inside the object
// (Eigen storage bounded at 6 and 6 x 6), so constructing, copying, predicting and updating never
// touch the heap: the robot loop runs one per track on every frame (frame_loop.h).
#pragma once

#include <Eigen/Core>

namespace ellipsekit::robot {

class ConstantVelocityKalman {
 public:
  static constexpr int kMaxDims = 3;
  using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, 2 * kMaxDims, 1>;
  using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, 2 * kMaxDims, 2 * kMaxDims>;

  // position: initial position (units, 1..3 values); position_var: its variance (units^2);
  // velocity_var: the initial velocity variance ((units/s)^2); accel_density: q; measurement_var:
  // R per axis.
  ConstantVelocityKalman(const Vector& position, double position_var, double velocity_var, double accel_density,
                         double measurement_var);

  int dims() const { return static_cast<int>(x_.size() / 2); }
  // Advance by dt seconds (dt <= 0 leaves the state unchanged).
  void Predict(double dt);
  // Fuse a position measurement (D values).
  void Update(const Vector& z);
  // Squared Mahalanobis distance of a measurement from the predicted position.
  double Mahalanobis2(const Vector& z) const;

  Vector position() const { return x_.head(dims()); }
  Vector velocity() const { return x_.tail(dims()); }
  // The position after a further dt, without changing the filter.
  Vector PredictedPosition(double dt) const { return position() + dt * velocity(); }
  const Vector& state() const { return x_; }
  const Matrix& covariance() const { return P_; }
  Matrix PositionCovariance() const { return P_.topLeftCorner(dims(), dims()); }

 private:
  Vector x_;
  Matrix P_;
  double q_;
  double r_;
};

}  // namespace ellipsekit::robot
