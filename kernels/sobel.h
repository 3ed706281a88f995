// sobel: 3x3 Sobel derivatives and their L1 magnitude, fused in one pass.
//
// Math:   dx(x, y) = sum_j w_j (src(x+1, y+j) - src(x-1, y+j)),  w = {1, 2, 1} for j = -1, 0, 1
//         dy(x, y) = sum_i w_i (src(x+i, y+1) - src(x+i, y-1))
//         mag(x, y) = |dx| + |dy|            (OpenCV Canny's default L1 norm)
// Range:  |dx|, |dy| <= 1020, mag <= 2040: int16 / uint16 hold them exactly.
// Border: replicate. Exact: integer only.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ellipsekit::scalar {

// src rows are src_stride bytes apart; dx, dy, mag rows are `stride` elements apart.
void Sobel(const std::uint8_t* src, std::ptrdiff_t src_stride, int width, int height,
           std::int16_t* dx, std::int16_t* dy, std::uint16_t* mag, std::ptrdiff_t stride);

}  // namespace ellipsekit::scalar
