// A read-only view of the edge stage's output as the fit back end's late checks read it, and the
// two tests they share: where the next edge pixel of a row is, and whether a gradient lies along
// an ellipse's normal.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace ellipsekit {

struct EdgeMapView {
  const std::uint8_t* edge_map;  // non-zero: edge pixel; rows `stride` bytes apart
  std::ptrdiff_t stride;
  const std::int16_t* dx;        // Sobel gradients, rows grad_stride elements apart
  const std::int16_t* dy;
  std::ptrdiff_t grad_stride;
  int width, height;
};

// The first x in [x, end) with row[x] != 0, or end. Edge pixels are sparse: empty runs are
// skipped 32, then 8 bytes at a time.
inline int FirstNonZeroByte(const std::uint8_t* row, int x, int end) {
  for (; x + 32 <= end; x += 32) {
    // Four loads into registers (one 32-byte copy into an array went through the stack).
    std::uint64_t w0, w1, w2, w3;
    std::memcpy(&w0, row + x, 8);
    std::memcpy(&w1, row + x + 8, 8);
    std::memcpy(&w2, row + x + 16, 8);
    std::memcpy(&w3, row + x + 24, 8);
    if ((w0 | w1 | w2 | w3) != 0) break;
  }
  for (; x + 8 <= end; x += 8) {
    std::uint64_t w;
    std::memcpy(&w, row + x, sizeof w);
    if (w == 0) continue;
    if constexpr (std::endian::native == std::endian::little) return x + std::countr_zero(w) / 8;
    break;
  }
  while (x < end && row[x] == 0) ++x;
  return x;
}

// True when the gradient (gx, gy) lies within ~26.6 degrees of the line of the normal (nx, ny),
// either sign: cos^2 >= 0.8, without a root or a division.
inline bool GradientAlongNormal(double gx, double gy, double nx, double ny) {
  constexpr double kMinCos2 = 0.8;
  const double dot = gx * nx + gy * ny;
  return dot * dot >= kMinCos2 * (gx * gx + gy * gy) * (nx * nx + ny * ny);
}

}  // namespace ellipsekit
