#include "fit/conic_refine.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

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
    const double phi = std::acos(arg) / 3;
    for (int k = 0; k < 3; ++k) roots[k] = shift + r * std::cos(phi - 2 * std::numbers::pi * k / 3);
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
  Eigen::Matrix2d q;
  q << A, B / 2, B / 2, C;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(q);
  const double l0 = es.eigenvalues()(0), l1 = es.eigenvalues()(1);
  const double s0 = -f0 / l0, s1 = -f0 / l1;
  if (!(s0 > 0) || !(s1 > 0)) return false;
  // The larger semi-axis goes with the eigenvalue of smaller magnitude.
  const bool first_major = s0 >= s1;
  const Eigen::Vector2d v = es.eigenvectors().col(first_major ? 0 : 1);
  out->cx = x0;
  out->cy = y0;
  out->a = std::sqrt(first_major ? s0 : s1);
  out->b = std::sqrt(first_major ? s1 : s0);
  out->theta = std::atan2(v.y(), v.x());
  NormalizeEllipse(out);
  return std::isfinite(out->cx) && std::isfinite(out->cy) && std::isfinite(out->a) && std::isfinite(out->b);
}

bool RefineEllipse(const Arc* const* arcs, int count, Ellipse* out) {
  // Centroid, then the central moments of the group (each arc's moments shifted to it).
  double n = 0, sx = 0, sy = 0;
  for (int i = 0; i < count; ++i) {
    const PointMoments& p = arcs[i]->moments;
    n += p.m[0][0];
    sx += p.m[1][0] + p.ox * p.m[0][0];
    sy += p.m[0][1] + p.oy * p.m[0][0];
  }
  if (n < 6) return false;
  PointMoments c;
  c.ox = sx / n;
  c.oy = sy / n;
  for (int i = 0; i < count; ++i) AddShiftedMoments(arcs[i]->moments, &c);
  // Normalised coordinates (x - mean) / scale with scale the RMS distance to the centroid.
  const double scale = std::sqrt((c.m[2][0] + c.m[0][2]) / n);
  if (!(scale > 0)) return false;
  double nm[kMomentOrder + 1][kMomentOrder + 1];  // normalised central moments
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
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(s3);
  if (!lu.isInvertible()) return false;
  const Eigen::Matrix3d t = -lu.solve(s2.transpose());
  const Eigen::Matrix3d m = s1 + s2 * t;
  Eigen::Matrix3d reduced;  // C1^-1 * m with the constraint 4ac - b^2 = 1
  reduced.row(0) = m.row(2) / 2;
  reduced.row(1) = -m.row(1);
  reduced.row(2) = m.row(0) / 2;
  Eigen::Vector3d a1;
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
