// Where an ellipse crosses a pixel row: the chord of each row and the ellipse's half extents, from
// its implicit form. The one geometry behind the row-by-row scans of an annulus along an outline
// (fit/edge_coverage.cc ClaimEdges / EdgePointsNear, fit/rim_search.cc FindOuterRim).
#pragma once

#include <cmath>

namespace ellipsekit {

// The ellipse with semi-axes A, B turned by theta, centred at the origin: p x^2 + 2 q x y + r y^2 = 1.
class EllipseRows {
 public:
  EllipseRows(double theta, double A, double B) {
    const double c = std::cos(theta), s = std::sin(theta), ia2 = 1 / (A * A), ib2 = 1 / (B * B);
    p_ = c * c * ia2 + s * s * ib2;
    q_ = c * s * (ia2 - ib2);
    r_ = s * s * ia2 + c * c * ib2;
    half_width_ = std::sqrt(A * A * c * c + B * B * s * s);
    half_height_ = std::sqrt(A * A * s * s + B * B * c * c);
  }
  double half_width() const { return half_width_; }
  double half_height() const { return half_height_; }
  // The chord [*x0, *x1] of the row dy (relative to the centre); false when the row misses the
  // ellipse or the form is degenerate (NaN).
  bool Span(double dy, double* x0, double* x1) const {
    const double q = q_ * dy, disc = q * q - p_ * (r_ * dy * dy - 1);
    if (!(disc >= 0)) return false;
    const double root = std::sqrt(disc);
    *x0 = (-q - root) / p_;
    *x1 = (-q + root) / p_;
    return true;
  }

 private:
  double p_, q_, r_, half_width_, half_height_;
};

}  // namespace ellipsekit
