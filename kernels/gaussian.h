// gaussian: 3x3 binomial smoothing, [1 2 1]^T [1 2 1] / 16.
//
// Math:   dst(x, y) = (sum_{i,j in -1..1} w_i w_j src(x+i, y+j) + 8) >> 4,  w = {1, 2, 1}.
// Border: replicate (src(-1, y) = src(0, y), and so on).
// Exact:  integer only; every backend returns the same bytes.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ellipsekit::scalar {

// src: width x height bytes, rows src_stride bytes apart; dst: rows dst_stride bytes apart.
void Gaussian(const std::uint8_t* src, std::ptrdiff_t src_stride, int width, int height,
              std::uint8_t* dst, std::ptrdiff_t dst_stride);

}  // namespace ellipsekit::scalar
