#include "fit/conic_refine.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

#include "fit/parameters.h"

namespace ellipsekit {

namespace {
constexpr int kMaxPointsPerArc = 128;
}

void RefineScratch::Reserve() {
  // Each arc contributes at most 2 * kMaxPointsPerArc points (step = n / kMaxPointsPerArc).
  x.reserve(3 * 2 * kMaxPointsPerArc + 3);
  y.reserve(3 * 2 * kMaxPointsPerArc + 3);
}

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

bool RefineEllipse(const Curves& curves, const Arc* const* arcs, int count, RefineScratch* s,
                   Ellipse* out) {
  s->x.clear();
  s->y.clear();
  for (int i = 0; i < count; ++i) {
    const Arc& arc = *arcs[i];
    const int n = arc.points();
    const int step = std::max(1, n / kMaxPointsPerArc);
    for (int p = arc.begin; p <= arc.end; p += step) {
      s->x.push_back(curves.x[p]);
      s->y.push_back(curves.y[p]);
    }
  }
  const int n = static_cast<int>(s->x.size());
  if (n < 6) return false;
  double mx = 0, my = 0;
  for (int i = 0; i < n; ++i) { mx += s->x[i]; my += s->y[i]; }
  mx /= n; my /= n;
  double scale = 0;
  for (int i = 0; i < n; ++i) scale += (s->x[i] - mx) * (s->x[i] - mx) + (s->y[i] - my) * (s->y[i] - my);
  scale = std::sqrt(scale / n);
  if (!(scale > 0)) return false;
  // Scatter matrices of the quadratic (x^2, xy, y^2) and linear (x, y, 1) parts.
  Eigen::Matrix3d s1 = Eigen::Matrix3d::Zero(), s2 = Eigen::Matrix3d::Zero(), s3 = Eigen::Matrix3d::Zero();
  for (int i = 0; i < n; ++i) {
    const double x = (s->x[i] - mx) / scale, y = (s->y[i] - my) / scale;
    const Eigen::Vector3d d1(x * x, x * y, y * y), d2(x, y, 1.0);
    s1 += d1 * d1.transpose();
    s2 += d1 * d2.transpose();
    s3 += d2 * d2.transpose();
  }
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
  e.cx = e.cx * scale + mx;
  e.cy = e.cy * scale + my;
  e.a *= scale;
  e.b *= scale;
  e.score = out->score;
  *out = e;
  return true;
}

}  // namespace ellipsekit
