// nms: Canny's non-maximum suppression with the two thresholds applied.
//
// Direction test in fixed point (no floats), as OpenCV's Canny does it:
//   ax = |dx|, ay = |dy|, kTan22 = round(tan(22.5 deg) * 2^15) = 13573, kTan67 = round(tan(67.5 deg) * 2^15) = 79109
//   (ay << 15) <  kTan22 * ax  -> gradient ~horizontal: neighbours (x-1, y), (x+1, y)
//   (ay << 15) >  kTan67 * ax  -> gradient ~vertical:   neighbours (x, y-1), (x, y+1)
//   otherwise diagonal: s = (dx, dy same sign) ? +1 : -1, neighbours (x-s, y-1), (x+s, y+1)
// A pixel is a local maximum when mag > the first neighbour and mag >= the second
// (diagonal: > both). Out: 0 = no edge, 1 = weak (local max, mag > low), 2 = strong (mag > high).
// Border: the outermost rows and columns are always 0.
// Exact: integer only.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ellipsekit {

inline constexpr std::int32_t kTan22Q15 = 13573;
inline constexpr std::int32_t kTan67Q15 = 79109;

enum NmsClass : std::uint8_t { kNmsNone = 0, kNmsWeak = 1, kNmsStrong = 2 };

namespace scalar {
// dx, dy, mag rows are `stride` elements apart; out rows are out_stride bytes apart.
void Nms(const std::int16_t* dx, const std::int16_t* dy, const std::uint16_t* mag, int width,
         int height, std::ptrdiff_t stride, int low, int high, std::uint8_t* out,
         std::ptrdiff_t out_stride);
}  // namespace scalar

}  // namespace ellipsekit
