#include "kernels/hysteresis.h"

#include <cstring>

#include "kernels/nms.h"

namespace ellipsekit {

namespace {
constexpr int kPackShift = 15;  // stack entries are (y << 15) | x: no division per pixel
static_assert((16384 << kPackShift) > 0, "y << kPackShift fits int32 for the 16384-px limit");

// True when one of the 8 bytes at p is kNmsStrong (the classic "has a zero byte" test on p ^ 2..2).
bool HasStrongByte(const std::uint8_t* p) {
  std::uint64_t w;
  std::memcpy(&w, p, sizeof w);
  const std::uint64_t x = w ^ (0x0101010101010101ull * kNmsStrong);
  return ((x - 0x0101010101010101ull) & ~x & 0x8080808080808080ull) != 0;
}
}  // namespace

void HysteresisFlood(std::uint8_t* map, int width, int height, std::ptrdiff_t stride,
                     std::int32_t* stack, int x, int y) {
  std::int64_t top = 0;
  auto reach = [&](int nx, int ny) {
    std::uint8_t& q = map[ny * stride + nx];
    if (q == kNmsWeak || q == kNmsStrong) {
      q = kHysteresisMark;
      stack[top++] = (ny << kPackShift) | nx;
    }
  };
  map[y * stride + x] = kHysteresisMark;
  stack[top++] = (y << kPackShift) | x;
  while (top > 0) {
    const std::int32_t packed = stack[--top];
    const int cy = packed >> kPackShift, cx = packed & ((1 << kPackShift) - 1);
    if (cx > 0 && cy > 0 && cx + 1 < width && cy + 1 < height) {  // interior: no bounds tests
      reach(cx - 1, cy - 1); reach(cx, cy - 1); reach(cx + 1, cy - 1);
      reach(cx - 1, cy);                         reach(cx + 1, cy);
      reach(cx - 1, cy + 1); reach(cx, cy + 1); reach(cx + 1, cy + 1);
      continue;
    }
    for (int ny = cy - 1; ny <= cy + 1; ++ny) {
      if (ny < 0 || ny >= height) continue;
      for (int nx = cx - 1; nx <= cx + 1; ++nx) {
        if (nx >= 0 && nx < width) reach(nx, ny);
      }
    }
  }
}

namespace scalar {

void Hysteresis(std::uint8_t* map, int width, int height, std::ptrdiff_t stride,
                std::int32_t* stack) {
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      // Strong pixels are rare: skip 8 at a time (the flood only ever writes kHysteresisMark,
      // so a word without a strong byte never gains one).
      if (x + 8 <= width && (x & 7) == 0 && !HasStrongByte(map + y * stride + x)) {
        x += 7;
        continue;
      }
      if (map[y * stride + x] == kNmsStrong) HysteresisFlood(map, width, height, stride, stack, x, y);
    }
  }
  for (int y = 0; y < height; ++y) {
    std::uint8_t* row = map + y * stride;
    for (int x = 0; x < width; ++x) row[x] = (row[x] == kHysteresisMark) ? 1 : 0;
  }
}

}  // namespace scalar
}  // namespace ellipsekit
