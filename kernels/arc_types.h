// Data handed between the curve tracer, the arc-stage kernels and the fit back end.
// All coordinates are integer pixel positions (x right, y down), so every arc-stage decision can
// be made in exact integer arithmetic. Frames are limited to kMaxImageDimension per side so that
// the products below fit int64 (see polyline.h and arc_split.h for the bounds).
#pragma once

#include <cstdint>
#include <vector>

namespace ellipsekit {

inline constexpr int kMaxImageDimension = 16384;

// Edge curves, struct-of-arrays; curve i holds points [offset[i], offset[i + 1]).
struct Curves {
  std::vector<std::int32_t> x, y;    // ordered 8-connected chain points
  std::vector<std::int16_t> gx, gy;  // Sobel gradient at each point
  std::vector<std::int32_t> offset;  // size = curves + 1
  std::vector<std::uint8_t> sign_class;  // per curve: kEdgePlus or kEdgeMinus

  int size() const { return offset.empty() ? 0 : static_cast<int>(offset.size()) - 1; }
  void clear() {
    x.clear(); y.clear(); gx.clear(); gy.clear(); sign_class.clear();
    offset.assign(1, 0);
  }
};

// Quadrants as seen on screen, counter-clockwise: I upper-right, II upper-left, III lower-left,
// IV lower-right. 0 = convexity undecided (the arc is dropped).
enum Quadrant : std::int8_t { kQuadrantNone = 0, kQuadrantI = 1, kQuadrantII = 2, kQuadrantIII = 3, kQuadrantIV = 4 };

// Per-arc statistics (arc_stats.h). An arc is the point range [begin, end] (inclusive) of a curve.
struct ArcStats {
  std::int32_t curve = 0, begin = 0, end = 0;
  std::int32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // first and last point
  std::int32_t xm = 0, ym = 0;                  // middle point, index (begin + end) / 2
  std::int32_t min_x = 0, min_y = 0, max_x = 0, max_y = 0;
  std::int32_t g0x = 0, g0y = 0, g1x = 0, g1y = 0;  // gradient sums over the first / last points
  std::int8_t quadrant = kQuadrantNone;
  std::uint8_t sign_class = 0;
  int points() const { return end - begin + 1; }
};

}  // namespace ellipsekit
