#include "kernels/hysteresis.h"

#include <cstring>

#include "kernels/nms.h"

namespace ellipsekit {

namespace {
// Stack entries are (from << 28) | (y << 14) | x: the move that reached the pixel (an index into
// kMoveX / kMoveY) and its position (14 bits each for the 16384-px limit); no division per pixel.
constexpr int kPackShift = 14;
constexpr std::int32_t kPackMask = (1 << kPackShift) - 1;
static_assert((7 << 2 * kPackShift) + (16383 << kPackShift) + 16383 > 0, "an entry fits int32");

constexpr int kMoveX[8] = {1, 1, 0, -1, -1, -1, 0, 1};
constexpr int kMoveY[8] = {0, 1, 1, 1, 0, -1, -1, -1};

// The neighbours of a pixel reached by move m that are not neighbours of the pixel it was reached
// from: 3 after a straight move (m even: m - 1, m, m + 1), 5 after a diagonal one (m - 2 .. m + 2),
// moves mod 8, clockwise on screen (y down). The parent's pop tested all of its own neighbours
// already, and one it left unmarked is neither weak nor strong. This check proves that rule from
// the move tables; the switch in HysteresisFlood spells it out, and conformance_hysteresis checks
// the switch itself against the contract.
constexpr bool IsNewNeighbour(int m, int k) {
  const int ox = kMoveX[m] + kMoveX[k], oy = kMoveY[m] + kMoveY[k];  // offset from the parent
  return ox * ox > 1 || oy * oy > 1;
}
constexpr bool NewNeighboursAreTheSwitchLists() {
  for (int m = 0; m < 8; ++m) {
    const int half = m % 2 == 0 ? 1 : 2;
    for (int k = 0; k < 8; ++k) {
      const int turn = (k - m + 8) % 8;  // 0..7, clockwise
      const bool listed = turn <= half || turn >= 8 - half;
      if (listed != IsNewNeighbour(m, k)) return false;
    }
  }
  return true;
}
static_assert(NewNeighboursAreTheSwitchLists());

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
  // Marks and pushes the neighbour along move k of the pixel at p, packed `at`, when it is weak
  // or strong (in the switch below k is a constant, so the offsets fold).
  auto reach = [&](std::uint8_t* p, std::int32_t at, int k) {
    std::uint8_t& q = p[kMoveY[k] * stride + kMoveX[k]];
    if (q == kNmsWeak || q == kNmsStrong) {
      q = kHysteresisMark;
      stack[top++] = (k << 2 * kPackShift) + at + kMoveY[k] * (1 << kPackShift) + kMoveX[k];
    }
  };
  // All 8 neighbours, clipped to the frame: the seed, and pixels on the frame's border.
  auto reach_all = [&](int cx, int cy) {
    std::uint8_t* p = map + cy * stride + cx;
    const std::int32_t at = (cy << kPackShift) | cx;
    for (int k = 0; k < 8; ++k) {
      const int nx = cx + kMoveX[k], ny = cy + kMoveY[k];
      if (nx >= 0 && nx < width && ny >= 0 && ny < height) reach(p, at, k);
    }
  };
  map[y * stride + x] = kHysteresisMark;
  reach_all(x, y);
  while (top > 0) {
    const std::int32_t packed = stack[--top];
    const int from = packed >> 2 * kPackShift;
    const std::int32_t at = packed & ((1 << 2 * kPackShift) - 1);
    const int cy = at >> kPackShift, cx = at & kPackMask;
    if (!(cx > 0 && cy > 0 && cx + 1 < width && cy + 1 < height)) {
      reach_all(cx, cy);
      continue;
    }
    // Interior: no bounds tests, and only the neighbours the parent did not test.
    std::uint8_t* p = map + cy * stride + cx;
    switch (from) {
      case 0: reach(p, at, 7); reach(p, at, 0); reach(p, at, 1); break;
      case 2: reach(p, at, 1); reach(p, at, 2); reach(p, at, 3); break;
      case 4: reach(p, at, 3); reach(p, at, 4); reach(p, at, 5); break;
      case 6: reach(p, at, 5); reach(p, at, 6); reach(p, at, 7); break;
      case 1: reach(p, at, 7); reach(p, at, 0); reach(p, at, 1); reach(p, at, 2); reach(p, at, 3); break;
      case 3: reach(p, at, 1); reach(p, at, 2); reach(p, at, 3); reach(p, at, 4); reach(p, at, 5); break;
      case 5: reach(p, at, 3); reach(p, at, 4); reach(p, at, 5); reach(p, at, 6); reach(p, at, 7); break;
      default: reach(p, at, 5); reach(p, at, 6); reach(p, at, 7); reach(p, at, 0); reach(p, at, 1); break;
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
