#include "kernels/pyramid_down.h"

namespace ellipsekit::scalar {

void PyramidDown(const std::uint8_t* src, std::ptrdiff_t src_stride, int width, int height,
                 std::uint8_t* dst, std::ptrdiff_t dst_stride) {
  const int w = width / 2, h = height / 2;
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* r0 = src + 2 * y * src_stride;
    const std::uint8_t* r1 = r0 + src_stride;
    std::uint8_t* out = dst + y * dst_stride;
    for (int x = 0; x < w; ++x) {
      const unsigned sum = r0[2 * x] + r0[2 * x + 1] + r1[2 * x] + r1[2 * x + 1];
      out[x] = static_cast<std::uint8_t>((sum + 2) >> 2);
    }
  }
}

}  // namespace ellipsekit::scalar
