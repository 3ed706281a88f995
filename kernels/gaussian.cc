#include "kernels/gaussian.h"

#include <algorithm>

namespace ellipsekit::scalar {

void Gaussian(const std::uint8_t* src, std::ptrdiff_t src_stride, int width, int height,
              std::uint8_t* dst, std::ptrdiff_t dst_stride) {
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* up = src + std::max(y - 1, 0) * src_stride;
    const std::uint8_t* mid = src + y * src_stride;
    const std::uint8_t* down = src + std::min(y + 1, height - 1) * src_stride;
    std::uint8_t* out = dst + y * dst_stride;
    for (int x = 0; x < width; ++x) {
      const int xl = std::max(x - 1, 0), xr = std::min(x + 1, width - 1);
      const int left = up[xl] + 2 * mid[xl] + down[xl];
      const int centre = up[x] + 2 * mid[x] + down[x];
      const int right = up[xr] + 2 * mid[xr] + down[xr];
      out[x] = static_cast<std::uint8_t>((left + 2 * centre + right + 8) >> 4);
    }
  }
}

}  // namespace ellipsekit::scalar
