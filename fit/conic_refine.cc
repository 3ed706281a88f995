#include "fit/conic_refine.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Dense>

#include "fit/parameters.h"

namespace ellipsekit {

namespace {

// The eigenvector of the reduced scatter matrix that is an ellipse (4ac - b^2 > 0, the largest
// such value for unit vectors), as Halir & Flusser pick it. The three eigenvalues are real (a
// symmetric-definite generalized problem), so they are the roots of the characteristic cubic by
// the trigonometric formula, and each eigenvector is the largest cross product of two rows of
// M - lambda I: a closed form, several times faster than a general 3x3 eigen solver.
bool EllipseEigenvector(const Eigen::Matrix3d& m, Eigen::Vector3d* out) {
  // lambda^3 - c2 lambda^2 + c1 lambda - c0 = 0.
  const double c2 = m.trace();
  const double c1 = m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0) + m(0, 0) * m(2, 2) - m(0, 2) * m(2, 0) +
                    m(1, 1) * m(2, 2) - m(1, 2) * m(2, 1);
  const double c0 = m.determinant();
  // lambda = mu + c2 / 3: mu^3 + p mu + q = 0.
  const double shift = c2 / 3;
  const double p = c1 - c2 * c2 / 3;
  const double q = -2 * c2 * c2 * c2 / 27 + c2 * c1 / 3 - c0;
  double roots[3];
  if (!(p < 0)) {  // a triple root (p = 0, so q = 0): mu = 0
    roots[0] = roots[1] = roots[2] = shift;
  } else {
    const double r = 2 * std::sqrt(-p / 3);
    const double arg = std::clamp(3 * q / (p * r), -1.0, 1.0);  // = cos(3 phi); rounding may leave [-1, 1]
    // phi in [0, pi/3], so sin(phi) >= 0; cos(phi -+ 2 pi / 3) by the angle-sum formula.
    const double cp = std::cos(std::acos(arg) / 3), sp = std::sqrt(std::max(0.0, 1 - cp * cp));
    constexpr double kSin120 = 0.86602540378443864676;
    roots[0] = shift + r * cp;
    roots[1] = shift + r * (-0.5 * cp + kSin120 * sp);
    roots[2] = shift + r * (-0.5 * cp - kSin120 * sp);
  }
  double best = 0;
  bool found = false;
  for (const double lambda : roots) {
    const Eigen::Matrix3d a = m - lambda * Eigen::Matrix3d::Identity();
    const Eigen::Vector3d r0 = a.row(0), r1 = a.row(1), r2 = a.row(2);
    Eigen::Vector3d v = r0.cross(r1);
    for (const Eigen::Vector3d& c : {r0.cross(r2), r1.cross(r2)}) {
      if (c.squaredNorm() > v.squaredNorm()) v = c;
    }
    const double norm = v.norm();
    if (!(norm > 0)) continue;
    v /= norm;
    const double cond = 4 * v(0) * v(2) - v(1) * v(1);
    if (cond > best) {
      best = cond;
      *out = v;
      found = true;
    }
  }
  return found;
}

}  // namespace

bool ConicToEllipse(const double k[6], Ellipse* out) {
  const double A = k[0], B = k[1], C = k[2], D = k[3], E = k[4], F = k[5];
  const double det = 4 * A * C - B * B;
  if (!(det > 0)) return false;
  const double x0 = (B * E - 2 * C * D) / det;
  const double y0 = (B * D - 2 * A * E) / det;
  const double f0 = F + 0.5 * (D * x0 + E * y0);
  // Eigenvalues of [[A, B/2], [B/2, C]]: m +- d, of equal sign (det > 0); the one nearer zero as
  // (det / 4) / (the other), without cancellation. The eigenvector of m + d is at phi.
  const double m = 0.5 * (A + C), d = std::sqrt(0.25 * (A - C) * (A - C) + 0.25 * B * B);
  const double phi = 0.5 * std::atan2(B, A - C);
  const double far = m > 0 ? m + d : m - d;  // larger magnitude: the minor axis
  const double near = 0.25 * det / far;      // smaller magnitude: the major axis
  const double s_major = -f0 / near, s_minor = -f0 / far;
  if (!(s_major > 0) || !(s_minor > 0)) return false;
  out->cx = x0;
  out->cy = y0;
  out->a = std::sqrt(s_major);
  out->b = std::sqrt(s_minor);
  out->theta = m > 0 ? phi + std::numbers::pi / 2 : phi;  // the eigenvector of `near`
  NormalizeEllipse(out);
  return std::isfinite(out->cx) && std::isfinite(out->cy) && std::isfinite(out->a) && std::isfinite(out->b);
}

bool RefineEllipse(const Arc* const* arcs, int count, Ellipse* out) {
  // The group's moments about the middle arc's origin (a point of the group's bounding box: the
  // other arcs' moments are shifted to it). Normalised coordinates (x - origin) / scale with scale
  // the RMS distance to the origin keep the scatter matrices well conditioned (Hartley).
  const PointMoments& middle = arcs[count / 2]->moments;
  PointMoments c = middle;
  for (int i = 0; i < count; ++i) {
    if (i != count / 2) AddShiftedMoments(arcs[i]->moments, &c);
  }
  const double n = c.m[0][0];
  if (n < 6) return false;
  const double scale = std::sqrt((c.m[2][0] + c.m[0][2]) / n);
  if (!(scale > 0)) return false;
  double nm[kMomentOrder + 1][kMomentOrder + 1];  // normalised moments
  double inv_scale_pow[2 * kMomentOrder + 1] = {1};  // scale^-k
  for (int k = 1; k <= 2 * kMomentOrder; ++k) inv_scale_pow[k] = inv_scale_pow[k - 1] / scale;
  for (int a = 0; a <= kMomentOrder; ++a) {
    for (int b = 0; a + b <= kMomentOrder; ++b) nm[a][b] = c.m[a][b] * inv_scale_pow[a + b];
  }
  // Scatter matrices of the quadratic (x^2, xy, y^2) and linear (x, y, 1) parts:
  // s1 = sum d1 d1^T, s2 = sum d1 d2^T, s3 = sum d2 d2^T.
  Eigen::Matrix3d s1, s2, s3;
  s1 << nm[4][0], nm[3][1], nm[2][2],
        nm[3][1], nm[2][2], nm[1][3],
        nm[2][2], nm[1][3], nm[0][4];
  s2 << nm[3][0], nm[2][1], nm[2][0],
        nm[2][1], nm[1][2], nm[1][1],
        nm[1][2], nm[0][3], nm[0][2];
  s3 << nm[2][0], nm[1][1], nm[1][0],
        nm[1][1], nm[0][2], nm[0][1],
        nm[1][0], nm[0][1], nm[0][0];
  // s3 is a Gram matrix: det(s3) / (product of its diagonal) is 0 for collinear points, <= 1.
  const double det3 = s3.determinant();
  if (!(det3 > 1e-12 * s3(0, 0) * s3(1, 1) * s3(2, 2))) return false;
  const Eigen::Matrix3d t = -(s3.inverse() * s2.transpose());
  const Eigen::Matrix3d m = s1 + s2 * t;
  Eigen::Matrix3d reduced;  // C1^-1 * m with the constraint 4ac - b^2 = 1
  reduced.row(0) = m.row(2) / 2;
  reduced.row(1) = -m.row(1);
  reduced.row(2) = m.row(0) / 2;
  Eigen::Vector3d a1 = Eigen::Vector3d::Zero();
  if (!EllipseEigenvector(reduced, &a1)) return false;
  const Eigen::Vector3d a2 = t * a1;
  const double conic[6] = {a1(0), a1(1), a1(2), a2(0), a2(1), a2(2)};
  Ellipse e;
  if (!ConicToEllipse(conic, &e)) return false;
  e.cx = e.cx * scale + c.ox;
  e.cy = e.cy * scale + c.oy;
  e.a *= scale;
  e.b *= scale;
  e.score = out->score;
  *out = e;
  return true;
}

}  // namespace ellipsekit
