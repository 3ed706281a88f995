#include "kernels/edge_sign.h"

namespace ellipsekit::scalar {

void EdgeSign(const std::uint8_t* edges, std::ptrdiff_t edge_stride, const std::int16_t* dx,
              const std::int16_t* dy, std::ptrdiff_t stride, int width, int height,
              std::uint8_t* out, std::ptrdiff_t out_stride) {
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* e = edges + y * edge_stride;
    const std::int16_t* gx = dx + y * stride;
    const std::int16_t* gy = dy + y * stride;
    std::uint8_t* o = out + y * out_stride;
    for (int x = 0; x < width; ++x) {
      const std::int32_t p = static_cast<std::int32_t>(gx[x]) * gy[x];
      o[x] = e[x] == 0 ? kEdgeNone : p > 0 ? kEdgePlus : p < 0 ? kEdgeMinus : kEdgeNone;
    }
  }
}

}  // namespace ellipsekit::scalar
