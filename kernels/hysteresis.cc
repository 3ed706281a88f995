#include "kernels/hysteresis.h"

#include "kernels/nms.h"

namespace ellipsekit::scalar {

namespace {
constexpr std::uint8_t kEdgeMark = 3;  // a strong or reached pixel, before the final relabel
}

void Hysteresis(std::uint8_t* map, int width, int height, std::ptrdiff_t stride,
                std::int32_t* stack) {
  std::int64_t top = 0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      std::uint8_t& p = map[y * stride + x];
      if (p != kNmsStrong) continue;
      p = kEdgeMark;
      stack[top++] = y * width + x;
      while (top > 0) {
        const std::int32_t idx = stack[--top];
        const int cy = idx / width, cx = idx - cy * width;
        for (int ny = cy - 1; ny <= cy + 1; ++ny) {
          if (ny < 0 || ny >= height) continue;
          for (int nx = cx - 1; nx <= cx + 1; ++nx) {
            if (nx < 0 || nx >= width) continue;
            std::uint8_t& q = map[ny * stride + nx];
            if (q == kNmsWeak || q == kNmsStrong) {
              q = kEdgeMark;
              stack[top++] = ny * width + nx;
            }
          }
        }
      }
    }
  }
  for (int y = 0; y < height; ++y) {
    std::uint8_t* row = map + y * stride;
    for (int x = 0; x < width; ++x) row[x] = (row[x] == kEdgeMark) ? 1 : 0;
  }
}

}  // namespace ellipsekit::scalar
