#include "fit/point_moments.h"

namespace ellipsekit {

namespace {

template <typename T>
PointMoments Moments(const T* x, const T* y, int begin, int end, T ox, T oy) {
  PointMoments p;
  p.ox = ox;
  p.oy = oy;
  for (int i = begin; i <= end; ++i) {
    const double dx = x[i] - ox, dy = y[i] - oy;
    double xa = 1;  // dx^a
    for (int a = 0; a <= kMomentOrder; ++a) {
      double yb = 1;  // dy^b
      for (int b = 0; a + b <= kMomentOrder; ++b) {
        p.m[a][b] += xa * yb;
        yb *= dy;
      }
      xa *= dx;
    }
  }
  return p;
}

}  // namespace

PointMoments MomentsOfPoints(const std::int32_t* x, const std::int32_t* y, int begin, int end,
                             std::int32_t ox, std::int32_t oy) {
  return Moments(x, y, begin, end, ox, oy);
}

PointMoments MomentsOfPoints(const double* x, const double* y, int begin, int end, double ox, double oy) {
  return Moments(x, y, begin, end, ox, oy);
}

void AddShiftedMoments(const PointMoments& p, PointMoments* acc) {
  // (x - acc.o) = (x - p.o) + d with d = p.o - acc.o. Shifting is separable: first x,
  //   t[a][b] = sum_{i<=a} C(a,i) dx^(a-i) p.m[i][b],
  // then y,
  //   acc.m[a][b] += sum_{j<=b} C(b,j) dy^(b-j) t[a][j].
  static constexpr double kBinomial[kMomentOrder + 1][kMomentOrder + 1] = {
      {1, 0, 0, 0, 0}, {1, 1, 0, 0, 0}, {1, 2, 1, 0, 0}, {1, 3, 3, 1, 0}, {1, 4, 6, 4, 1}};
  const double dx = p.ox - acc->ox, dy = p.oy - acc->oy;
  double px[kMomentOrder + 1], py[kMomentOrder + 1];
  px[0] = py[0] = 1;
  for (int k = 1; k <= kMomentOrder; ++k) {
    px[k] = px[k - 1] * dx;
    py[k] = py[k - 1] * dy;
  }
  double t[kMomentOrder + 1][kMomentOrder + 1] = {};
  for (int a = 0; a <= kMomentOrder; ++a) {
    for (int b = 0; a + b <= kMomentOrder; ++b) {
      for (int i = 0; i <= a; ++i) t[a][b] += kBinomial[a][i] * px[a - i] * p.m[i][b];
    }
  }
  for (int a = 0; a <= kMomentOrder; ++a) {
    for (int b = 0; a + b <= kMomentOrder; ++b) {
      double s = 0;
      for (int j = 0; j <= b; ++j) s += kBinomial[b][j] * py[b - j] * t[a][j];
      acc->m[a][b] += s;
    }
  }
}

}  // namespace ellipsekit
