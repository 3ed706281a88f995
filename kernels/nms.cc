#include "kernels/nms.h"

#include <cstring>

namespace ellipsekit::scalar {

void Nms(const std::int16_t* dx, const std::int16_t* dy, const std::uint16_t* mag, int width,
         int height, std::ptrdiff_t stride, const NmsThresholds& th, std::uint8_t* out,
         std::ptrdiff_t out_stride) {
  for (int y = 0; y < height; ++y) {
    std::uint8_t* o = out + y * out_stride;
    std::memset(o, 0, static_cast<std::size_t>(width));
    if (y == 0 || y == height - 1) continue;
    const std::uint16_t* mp = mag + (y - 1) * stride;
    const std::uint16_t* mc = mag + y * stride;
    const std::uint16_t* mn = mag + (y + 1) * stride;
    const std::int16_t* gx = dx + y * stride;
    const std::int16_t* gy = dy + y * stride;
    const std::int32_t* low_row = th.low + (y >> th.shift) * th.tiles_x;
    const std::int32_t* high_row = th.high + (y >> th.shift) * th.tiles_x;
    for (int x = 1; x < width - 1; ++x) {
      o[x] = NmsPixel(mp, mc, mn, gx, gy, x, low_row[x >> th.shift], high_row[x >> th.shift]);
    }
  }
}

}  // namespace ellipsekit::scalar
