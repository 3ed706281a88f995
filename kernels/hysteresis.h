// hysteresis: Canny's edge tracking by hysteresis.
//
// Contract (order independent, so every backend can reach it its own way): a pixel is an edge
// exactly when it is weak or strong (nms.h) and lies in an 8-connected component of such pixels
// that holds at least one strong pixel. Out: 1 = edge, 0 = not. In-place on the NMS map.
// Sizes up to 16384 px a side (detect()'s limit; stack entries pack y and x in 14 bits each).
// The scalar reference floods from every strong pixel with an explicit stack (`stack` must hold
// width * height entries); a parallel backend may iterate "weak with an edge neighbour becomes
// edge" until nothing changes, which ends after at most width * height rounds.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ellipsekit {

// What a flood writes over each pixel it reaches, before the final relabel to 1 / 0.
inline constexpr std::uint8_t kHysteresisMark = 3;

// The flood both CPU versions share: marks the strong pixel (x, y) and every weak or strong pixel
// 8-connected to it with kHysteresisMark. `stack` as for Hysteresis. A pixel once marked is never
// pushed again, so a frame's floods together push each pixel at most once. A popped pixel tests
// only the neighbours its parent did not (3 or 5 of 8; all 8 on the frame's border).
void HysteresisFlood(std::uint8_t* map, int width, int height, std::ptrdiff_t stride,
                     std::int32_t* stack, int x, int y);

namespace scalar {

void Hysteresis(std::uint8_t* map, int width, int height, std::ptrdiff_t stride,
                std::int32_t* stack);

}  // namespace scalar
}  // namespace ellipsekit
