// pyramid_down: one level of the image pyramid, 2x2 box average.
//
// Math:   dst(x, y) = (src(2x, 2y) + src(2x+1, 2y) + src(2x, 2y+1) + src(2x+1, 2y+1) + 2) >> 2
//         for x < width / 2, y < height / 2 (an odd last column or row is dropped).
// Geometry: dst pixel (x, y) covers src pixels 2x..2x+1, 2y..2y+1, so a point at u in dst (pixel
//         centres at integers) is at 2u + 0.5 in src: PyramidUp below.
// Exact:  integer only; every backend reduces on the CPU with this function, so all agree.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ellipsekit::scalar {

// src: width x height bytes, rows src_stride bytes apart; dst: (width / 2) x (height / 2), rows
// dst_stride bytes apart. width and height >= 2.
void PyramidDown(const std::uint8_t* src, std::ptrdiff_t src_stride, int width, int height,
                 std::uint8_t* dst, std::ptrdiff_t dst_stride);

}  // namespace ellipsekit::scalar

namespace ellipsekit {

// A coordinate of level `level` (0: the frame) at level 0.
inline double PyramidUp(double u, int level) {
  const double s = static_cast<double>(1 << level);
  return (u + 0.5) * s - 0.5;
}

}  // namespace ellipsekit
