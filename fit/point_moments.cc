#include "fit/point_moments.h"

namespace ellipsekit {

PointMoments MomentsOfPoints(const std::int32_t* x, const std::int32_t* y, int begin, int end,
                             std::int32_t ox, std::int32_t oy) {
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

void AddShiftedMoments(const PointMoments& p, PointMoments* acc) {
  // (x - acc.o) = (x - p.o) + d with d = p.o - acc.o:
  //   sum (x - acc.ox)^a (y - acc.oy)^b = sum_{i<=a, j<=b} C(a,i) C(b,j) dx^(a-i) dy^(b-j) p.m[i][j].
  static constexpr double kBinomial[kMomentOrder + 1][kMomentOrder + 1] = {
      {1, 0, 0, 0, 0}, {1, 1, 0, 0, 0}, {1, 2, 1, 0, 0}, {1, 3, 3, 1, 0}, {1, 4, 6, 4, 1}};
  const double dx = p.ox - acc->ox, dy = p.oy - acc->oy;
  double px[kMomentOrder + 1], py[kMomentOrder + 1];
  px[0] = py[0] = 1;
  for (int k = 1; k <= kMomentOrder; ++k) {
    px[k] = px[k - 1] * dx;
    py[k] = py[k - 1] * dy;
  }
  for (int a = 0; a <= kMomentOrder; ++a) {
    for (int b = 0; a + b <= kMomentOrder; ++b) {
      double s = 0;
      for (int i = 0; i <= a; ++i) {
        for (int j = 0; j <= b; ++j) s += kBinomial[a][i] * kBinomial[b][j] * px[a - i] * py[b - j] * p.m[i][j];
      }
      acc->m[a][b] += s;
    }
  }
}

}  // namespace ellipsekit
