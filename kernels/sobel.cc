#include "kernels/sobel.h"

#include <algorithm>
#include <cstdlib>

namespace ellipsekit::scalar {

void Sobel(const std::uint8_t* src, std::ptrdiff_t src_stride, int width, int height,
           std::int16_t* dx, std::int16_t* dy, std::uint16_t* mag, std::ptrdiff_t stride) {
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* up = src + std::max(y - 1, 0) * src_stride;
    const std::uint8_t* mid = src + y * src_stride;
    const std::uint8_t* down = src + std::min(y + 1, height - 1) * src_stride;
    for (int x = 0; x < width; ++x) {
      const int xl = std::max(x - 1, 0), xr = std::min(x + 1, width - 1);
      const int gx = (up[xr] + 2 * mid[xr] + down[xr]) - (up[xl] + 2 * mid[xl] + down[xl]);
      const int gy = (down[xl] + 2 * down[x] + down[xr]) - (up[xl] + 2 * up[x] + up[xr]);
      const std::ptrdiff_t i = y * stride + x;
      dx[i] = static_cast<std::int16_t>(gx);
      dy[i] = static_cast<std::int16_t>(gy);
      mag[i] = static_cast<std::uint16_t>(std::abs(gx) + std::abs(gy));
    }
  }
}

}  // namespace ellipsekit::scalar
