// edge_sign: the gradient-sign class of each edge pixel (paper eq. 1).
//
//   out = 1 ("+") when edge and dx * dy > 0
//   out = 2 ("-") when edge and dx * dy < 0
//   out = 0 otherwise; edge pixels with dx == 0 or dy == 0 are dropped (sec. II-A).
// In image coordinates (y down), "+" edges lie on the upper-left and lower-right quarters of an
// ellipse (tangent slope > 0 on screen is "\"), "-" on the upper-right and lower-left ones.
// Exact: integer only (|dx * dy| <= 1020^2 fits int32).
#pragma once

#include <cstddef>
#include <cstdint>

namespace ellipsekit {

enum EdgeClass : std::uint8_t { kEdgeNone = 0, kEdgePlus = 1, kEdgeMinus = 2 };

namespace scalar {
// edges: 0/1 map (hysteresis.h), rows edge_stride bytes apart; dx, dy rows `stride` elements
// apart; out rows out_stride bytes apart. out may alias edges.
void EdgeSign(const std::uint8_t* edges, std::ptrdiff_t edge_stride, const std::int16_t* dx,
              const std::int16_t* dy, std::ptrdiff_t stride, int width, int height,
              std::uint8_t* out, std::ptrdiff_t out_stride);
}  // namespace scalar

}  // namespace ellipsekit
