#include "tools/eval/overlap.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ellipsekit::eval {
namespace {

bool IsValid(const Ellipse& e) {
  return std::isfinite(e.cx) && std::isfinite(e.cy) && std::isfinite(e.a) && std::isfinite(e.b) &&
         std::isfinite(e.theta) && e.a > 0 && e.b > 0;
}

struct Vec2 {
  double x, y;
};

double Cross(Vec2 u, Vec2 v) { return u.x * v.y - u.y * v.x; }
double Dot(Vec2 u, Vec2 v) { return u.x * v.x + u.y * v.y; }

// Signed area of (triangle (0, u, v)) ∩ (unit disc), for a segment u -> v wholly inside or
// wholly outside the disc: inside it is the triangle, outside the circular sector (0, u, v).
double Piece(Vec2 u, Vec2 v) {
  const Vec2 mid{0.5 * (u.x + v.x), 0.5 * (u.y + v.y)};
  if (Dot(mid, mid) <= 1.0) return 0.5 * Cross(u, v);
  return 0.5 * std::atan2(Cross(u, v), Dot(u, v));
}

// Signed area of (triangle (0, u, v)) ∩ (unit disc): split u -> v where it crosses the circle.
double EdgeTerm(Vec2 u, Vec2 v) {
  const Vec2 d{v.x - u.x, v.y - u.y};
  const double qa = Dot(d, d);
  if (qa == 0) return 0;
  const double qb = Dot(u, d);  // half of the linear coefficient
  const double qc = Dot(u, u) - 1.0;
  const double disc = qb * qb - qa * qc;
  if (disc <= 0) return Piece(u, v);  // the line misses (or touches) the circle
  const double root = std::sqrt(disc);
  const double t1 = (-qb - root) / qa;
  const double t2 = (-qb + root) / qa;
  Vec2 points[4];
  int n = 0;
  points[n++] = u;
  if (t1 > 0 && t1 < 1) points[n++] = {u.x + t1 * d.x, u.y + t1 * d.y};
  if (t2 > 0 && t2 < 1) points[n++] = {u.x + t2 * d.x, u.y + t2 * d.y};
  points[n++] = v;
  double sum = 0;
  for (int i = 0; i + 1 < n; ++i) sum += Piece(points[i], points[i + 1]);
  return sum;
}

}  // namespace

BoundingBox EllipseBounds(const Ellipse& e) {
  const double c = std::cos(e.theta), s = std::sin(e.theta);
  const double hx = std::sqrt(e.a * e.a * c * c + e.b * e.b * s * s);
  const double hy = std::sqrt(e.a * e.a * s * s + e.b * e.b * c * c);
  return {e.cx - hx, e.cy - hy, e.cx + hx, e.cy + hy};
}

double EllipseIntersectionArea(const Ellipse& p, const Ellipse& q) {
  if (!IsValid(p) || !IsValid(q)) return 0;
  const BoundingBox bp = EllipseBounds(p), bq = EllipseBounds(q);
  if (bp.x1 <= bq.x0 || bq.x1 <= bp.x0 || bp.y1 <= bq.y0 || bq.y1 <= bp.y0) return 0;

  // The affine map that takes P to the unit disc: rotate by -theta_p about P's centre, then
  // divide by the semi-axes. Its determinant is 1 / (a_p b_p).
  const double cp = std::cos(p.theta), sp = std::sin(p.theta);
  const double cq = std::cos(q.theta), sq = std::sin(q.theta);
  auto to_unit = [&](double x, double y) {
    const double dx = x - p.cx, dy = y - p.cy;
    return Vec2{(cp * dx + sp * dy) / p.a, (-sp * dx + cp * dy) / p.b};
  };

  // Q's polygon: vertices at equal steps of Q's parameter t, radially scaled so that its area is
  // the ellipse's (the inscribed N-gon has area pi*a*b * sin(2pi/N) / (2pi/N)). Increasing t has
  // positive orientation for Cross, and the map to P's frame keeps it (rotation, positive scale).
  constexpr int n = kOverlapPolygonVertices;
  const double step = 2 * std::numbers::pi / n;
  const double scale = std::sqrt(step / std::sin(step));
  const double qa = q.a * scale, qb = q.b * scale;
  Vec2 first{}, prev{};
  double sum = 0;
  for (int k = 0; k <= n; ++k) {
    Vec2 cur;
    if (k == n) {
      cur = first;
    } else {
      const double t = k * step;
      const double ex = qa * std::cos(t), ey = qb * std::sin(t);
      cur = to_unit(q.cx + cq * ex - sq * ey, q.cy + sq * ex + cq * ey);
    }
    if (k == 0) {
      first = cur;
    } else {
      sum += EdgeTerm(prev, cur);
    }
    prev = cur;
  }
  // The sum is positive (see above); fabs and the clamp only guard against rounding.
  const double unit_area = std::clamp(std::fabs(sum), 0.0, std::numbers::pi);
  return unit_area * p.a * p.b;
}

double EllipseJaccard(const Ellipse& p, const Ellipse& q) {
  if (!IsValid(p) || !IsValid(q)) return 0;
  const double inter = EllipseIntersectionArea(p, q);
  if (inter <= 0) return 0;
  const double area_p = std::numbers::pi * p.a * p.b;
  const double area_q = std::numbers::pi * q.a * q.b;
  const double inter_clamped = std::min(inter, std::min(area_p, area_q));
  const double uni = area_p + area_q - inter_clamped;
  if (!(uni > 0)) return 0;
  return std::clamp(inter_clamped / uni, 0.0, 1.0);
}

}  // namespace ellipsekit::eval
