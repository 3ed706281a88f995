// Constant-velocity Kalman filter (see kalman.h). Every temporary is one of the bounded types, so
// nothing here allocates.
#include "ellipsekit/robot/kalman.h"

#include <Eigen/Dense>

namespace ellipsekit::robot {

ConstantVelocityKalman::ConstantVelocityKalman(const Vector& position, double position_var, double velocity_var,
                                               double accel_density, double measurement_var)
    : q_(accel_density), r_(measurement_var) {
  const int d = static_cast<int>(position.size());
  x_ = Vector::Zero(2 * d);
  x_.head(d) = position;
  P_ = Matrix::Zero(2 * d, 2 * d);
  P_.topLeftCorner(d, d).diagonal().setConstant(position_var);
  P_.bottomRightCorner(d, d).diagonal().setConstant(velocity_var);
}

void ConstantVelocityKalman::Predict(double dt) {
  if (!(dt > 0)) return;
  const int d = dims();
  // x' = F x with F = [I dt I; 0 I]; P' = F P F^T + Q, written out per block so that no 2D x 2D
  // product is formed. Discrete white-noise acceleration: Q = q [dt^3/3, dt^2/2; dt^2/2, dt] per axis.
  x_.head(d) += dt * x_.tail(d);
  const Matrix Ppp = P_.topLeftCorner(d, d), Ppv = P_.topRightCorner(d, d), Pvv = P_.bottomRightCorner(d, d);
  Matrix npp = Ppp + dt * (Ppv + Ppv.transpose()) + dt * dt * Pvv;
  Matrix npv = Ppv + dt * Pvv;
  npp.diagonal().array() += q_ * dt * dt * dt / 3;
  npv.diagonal().array() += q_ * dt * dt / 2;
  P_.topLeftCorner(d, d) = npp;
  P_.topRightCorner(d, d) = npv;
  P_.bottomLeftCorner(d, d) = npv.transpose();
  P_.bottomRightCorner(d, d).diagonal().array() += q_ * dt;
}

void ConstantVelocityKalman::Update(const Vector& z) {
  const int d = dims();
  Matrix S = P_.topLeftCorner(d, d);
  S.diagonal().array() += r_;
  const Matrix PHt = P_.leftCols(d);  // P H^T with H = [I 0]
  const Matrix Kg = PHt * S.inverse();
  const Vector y = z - x_.head(d);
  x_ += Kg * y;
  P_ -= Kg * PHt.transpose();
  const Matrix Pt = P_.transpose();
  P_ = 0.5 * (P_ + Pt);
}

double ConstantVelocityKalman::Mahalanobis2(const Vector& z) const {
  const int d = dims();
  Matrix S = P_.topLeftCorner(d, d);
  S.diagonal().array() += r_;
  const Vector y = z - x_.head(d);
  const Vector w = S.ldlt().solve(y);
  return y.dot(w);
}

}  // namespace ellipsekit::robot
