// Shared by the fit and detector tests: a reference ellipse with exact points and normals, and
// the bit-for-bit comparison of detected ellipse lists that the backend, stream and thread
// contracts ask for (DESIGN.md "Exactness").
#pragma once

#include <cmath>
#include <cstring>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "ellipsekit/types.h"

namespace ellipsekit::test {

// A reference ellipse (OpenCV RotatedRect convention: major axis along (cos theta, sin theta)).
struct TrueEllipse {
  double cx, cy, a, b, theta;

  Eigen::Vector2d Point(double t) const {
    const double c = std::cos(theta), s = std::sin(theta);
    const double u = a * std::cos(t), v = b * std::sin(t);
    return {cx + c * u - s * v, cy + s * u + c * v};
  }
  // Outward unit normal at Point(t): the gradient of (xo/a)^2 + (yo/b)^2 - 1 there, normalised.
  Eigen::Vector2d Normal(double t) const {
    const double c = std::cos(theta), s = std::sin(theta);
    const double gu = std::cos(t) / a, gv = std::sin(t) / b;
    return Eigen::Vector2d(c * gu - s * gv, s * gu + c * gv).normalized();
  }
  // Unit normal at any point p (the implicit function's gradient there).
  Eigen::Vector2d NormalAt(const Eigen::Vector2d& p) const {
    const double c = std::cos(theta), s = std::sin(theta);
    const double dx = p.x() - cx, dy = p.y() - cy;
    const double xo = dx * c + dy * s, yo = -dx * s + dy * c;
    const double gu = xo / (a * a), gv = yo / (b * b);
    return Eigen::Vector2d(c * gu - s * gv, s * gu + c * gv).normalized();
  }
  // (xo / a)^2 + (yo / b)^2 - 1 at p (the paper's eq. 14).
  double Algebraic(const Eigen::Vector2d& p) const {
    const double c = std::cos(theta), s = std::sin(theta);
    const double dx = p.x() - cx, dy = p.y() - cy;
    const double xo = dx * c + dy * s, yo = dy * c - dx * s;
    return xo * xo / (a * a) + yo * yo / (b * b) - 1;
  }
  Ellipse AsEllipse() const {
    Ellipse e;
    e.cx = cx;
    e.cy = cy;
    e.a = a;
    e.b = b;
    e.theta = theta;
    return e;
  }
};

inline bool SameBits(double x, double y) { return std::memcmp(&x, &y, sizeof x) == 0; }

// The same list, in the same order, every field (score included) the same bits.
inline ::testing::AssertionResult SameEllipses(const std::vector<Ellipse>& a, const std::vector<Ellipse>& b) {
  if (a.size() != b.size()) return ::testing::AssertionFailure() << a.size() << " vs " << b.size() << " ellipses";
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Ellipse &x = a[i], &y = b[i];
    if (!SameBits(x.cx, y.cx) || !SameBits(x.cy, y.cy) || !SameBits(x.a, y.a) || !SameBits(x.b, y.b) ||
        !SameBits(x.theta, y.theta) || !SameBits(x.score, y.score))
      return ::testing::AssertionFailure() << "ellipse " << i << " differs: (" << x.cx << ", " << x.cy << ", " << x.a
                                           << ", " << x.b << ", " << x.theta << ", " << x.score << ") vs (" << y.cx
                                           << ", " << y.cy << ", " << y.a << ", " << y.b << ", " << y.theta << ", "
                                           << y.score << ")";
  }
  return ::testing::AssertionSuccess();
}

}  // namespace ellipsekit::test
