#include "tools/scenes/conic.h"

#include <algorithm>
#include <cmath>

namespace ellipsekit::scenes {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

double NormalizeAxisAngle(double theta) {
  double t = std::fmod(theta + kPi / 2, kPi);
  if (t < 0) t += kPi;
  double r = t - kPi / 2;
  if (r >= kPi / 2) r -= kPi;  // fmod rounding can land exactly on the open end
  if (r < -kPi / 2) r = -kPi / 2;
  return r + 0.0;  // turns -0.0 into +0.0
}

bool ConicToEllipse(const cv::Matx33d& q_in, ellipsekit::Ellipse* out) {
  if (out == nullptr) return false;
  // Symmetrise and scale to unit max entry so the tolerances below are relative.
  cv::Matx33d q = (q_in + q_in.t()) * 0.5;
  double scale = 0;
  for (int i = 0; i < 9; ++i) {
    if (!std::isfinite(q.val[i])) return false;
    scale = std::max(scale, std::abs(q.val[i]));
  }
  if (scale == 0) return false;
  q *= 1.0 / scale;
  double A = q(0, 0), Bh = q(0, 1), C = q(1, 1), Dh = q(0, 2), Eh = q(1, 2), F = q(2, 2);
  const double det2 = A * C - Bh * Bh;
  const double m_scale = std::max({std::abs(A), std::abs(C), std::abs(Bh)});
  if (!(det2 > 1e-14 * m_scale * m_scale)) return false;  // not an ellipse (or degenerate)
  const double cx = (Bh * Eh - C * Dh) / det2;
  const double cy = (Bh * Dh - A * Eh) / det2;
  double k = -(F + Dh * cx + Eh * cy);
  if (A + C < 0) {  // fix the sign so M is positive definite
    A = -A;
    Bh = -Bh;
    C = -C;
    k = -k;
  }
  if (!(k > 0)) return false;  // imaginary ellipse or a single point
  const double mean = 0.5 * (A + C);
  const double half_diff = 0.5 * (A - C);
  const double dev = std::sqrt(half_diff * half_diff + Bh * Bh);
  const double l_small = mean - dev;
  const double l_large = mean + dev;
  if (!(l_small > 0)) return false;
  ellipsekit::Ellipse e;
  e.cx = cx;
  e.cy = cy;
  e.a = std::sqrt(k / l_small);
  e.b = std::sqrt(k / l_large);
  e.theta = dev <= 1e-15 * mean ? 0.0 : NormalizeAxisAngle(0.5 * std::atan2(-2 * Bh, C - A));
  e.score = 0;
  if (!std::isfinite(e.cx) || !std::isfinite(e.cy) || !std::isfinite(e.a) || !std::isfinite(e.b)) return false;
  *out = e;
  return true;
}

cv::Matx33d EllipseToConic(const ellipsekit::Ellipse& e) {
  const double c = std::cos(e.theta), s = std::sin(e.theta);
  const double ia = 1.0 / (e.a * e.a), ib = 1.0 / (e.b * e.b);
  // M = R diag(1/a^2, 1/b^2) R^T with R's first column the major axis.
  const double m00 = c * c * ia + s * s * ib;
  const double m01 = c * s * (ia - ib);
  const double m11 = s * s * ia + c * c * ib;
  const double d0 = -(m00 * e.cx + m01 * e.cy);
  const double d1 = -(m01 * e.cx + m11 * e.cy);
  const double f = m00 * e.cx * e.cx + 2 * m01 * e.cx * e.cy + m11 * e.cy * e.cy - 1.0;
  return cv::Matx33d(m00, m01, d0, m01, m11, d1, d0, d1, f);
}

cv::Matx33d ProjectCircleConic(const cv::Matx33d& K, const cv::Matx33d& R, const cv::Vec3d& t,
                               const cv::Vec3d& centre, const cv::Vec3d& u, const cv::Vec3d& v,
                               double radius) {
  const cv::Vec3d h0 = K * (R * (u * radius));
  const cv::Vec3d h1 = K * (R * (v * radius));
  const cv::Vec3d h2 = K * (R * centre + t);
  cv::Matx33d H(h0[0], h1[0], h2[0], h0[1], h1[1], h2[1], h0[2], h1[2], h2[2]);
  const cv::Matx33d Hi = H.inv(cv::DECOMP_LU);
  const cv::Matx33d D(1, 0, 0, 0, 1, 0, 0, 0, -1);
  return Hi.t() * D * Hi;
}

}  // namespace ellipsekit::scenes
