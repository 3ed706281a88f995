#include "fit/conic_refine.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

#include "fit/parameters.h"

namespace ellipsekit {

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
  for (int a = 0; a <= kMomentOrder; ++a) {
    for (int b = 0; a + b <= kMomentOrder; ++b) nm[a][b] = c.m[a][b] / std::pow(scale, a + b);
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
  const Eigen::EigenSolver<Eigen::Matrix3d> es(reduced);
  int pick = -1;
  double best = 0;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d v = es.eigenvectors().col(i).real();
    const double cond = 4 * v(0) * v(2) - v(1) * v(1);
    if (cond > best) { best = cond; pick = i; }
  }
  if (pick < 0) return false;
  const Eigen::Vector3d a1 = es.eigenvectors().col(pick).real();
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
