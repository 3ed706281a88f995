// nms: Canny's non-maximum suppression with the two thresholds applied.
//
// Direction test in fixed point (no floats), as OpenCV's Canny does it:
//   ax = |dx|, ay = |dy|, kTan22 = round(tan(22.5 deg) * 2^15) = 13573, kTan67 = round(tan(67.5 deg) * 2^15) = 79109
//   (ay << 15) <  kTan22 * ax  -> gradient ~horizontal: neighbours (x-1, y), (x+1, y)
//   (ay << 15) >  kTan67 * ax  -> gradient ~vertical:   neighbours (x, y-1), (x, y+1)
//   otherwise diagonal: s = (dx, dy same sign) ? +1 : -1, neighbours (x-s, y-1), (x+s, y+1)
// A pixel is a local maximum when mag > the first neighbour and mag >= the second
// (diagonal: > both). Out: 0 = no edge, 1 = weak (local max, mag > low), 2 = strong (mag > high),
// low and high those of the pixel's tile (NmsThresholds; one tile: the classic one pair per frame).
// Border: the outermost rows and columns are always 0.
// Exact: integer only.
// Domain: the Sobel's planes (|dx|, |dy| <= 1020, mag = |dx| + |dy|); a backend may rely on
// |dx|, |dy| <= 16383 and mag <= 32767 (the Highway one works in 16-bit lanes).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>

namespace ellipsekit {

inline constexpr std::int32_t kTan22Q15 = 13573;
inline constexpr std::int32_t kTan67Q15 = 79109;

enum NmsClass : std::uint8_t { kNmsNone = 0, kNmsWeak = 1, kNmsStrong = 2 };

// Smallest tile: 32 px, so a SIMD vector run and a shader's 32-pixel mask word each lie in one tile.
inline constexpr int kNmsMinTileShift = 5;
// One tile covers any frame detect() accepts (16384 px a side).
inline constexpr int kNmsOneTileShift = 14;

// The thresholds per square tile of 2^shift px (shift in [kNmsMinTileShift, kNmsOneTileShift]):
// pixel (x, y) reads low[t] and high[t], t = (y >> shift) * tiles_x + (x >> shift).
struct NmsThresholds {
  int shift = kNmsOneTileShift;
  int tiles_x = 1;
  const std::int32_t* low = nullptr;
  const std::int32_t* high = nullptr;
};

// Interior pixel x of a row, as the contract above classifies it: mp, mc, mn the magnitudes of
// the rows above, at and below it; gx, gy its row of the gradient; low, high its tile's pair.
// The one statement of the per-pixel rule: the scalar reference runs it on every pixel, the
// Highway version on the tail of each run shorter than a vector.
inline NmsClass NmsPixel(const std::uint16_t* mp, const std::uint16_t* mc, const std::uint16_t* mn,
                         const std::int16_t* gx, const std::int16_t* gy, int x, int low, int high) {
  const int m = mc[x];
  if (m <= low) return kNmsNone;
  const std::int32_t ax = std::abs(gx[x]), ay = std::abs(gy[x]);
  const std::int32_t ay15 = ay << 15;
  bool is_max;
  if (ay15 < kTan22Q15 * ax) {
    is_max = m > mc[x - 1] && m >= mc[x + 1];
  } else if (ay15 > kTan67Q15 * ax) {
    is_max = m > mp[x] && m >= mn[x];
  } else {
    const int s = ((gx[x] ^ gy[x]) < 0) ? -1 : 1;
    is_max = m > mp[x - s] && m > mn[x + s];
  }
  if (!is_max) return kNmsNone;
  return m > high ? kNmsStrong : kNmsWeak;
}

// One pair for the whole frame (classic Canny); view() lives as long as the pair.
struct NmsOnePair {
  std::int32_t low = 0;
  std::int32_t high = 0;
  NmsThresholds view() const { return {kNmsOneTileShift, 1, &low, &high}; }
};

namespace scalar {
// dx, dy, mag rows are `stride` elements apart; out rows are out_stride bytes apart.
void Nms(const std::int16_t* dx, const std::int16_t* dy, const std::uint16_t* mag, int width,
         int height, std::ptrdiff_t stride, const NmsThresholds& th, std::uint8_t* out,
         std::ptrdiff_t out_stride);
}  // namespace scalar

}  // namespace ellipsekit
