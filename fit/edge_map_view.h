// A read-only view of the edge stage's output as the fit back end's late checks read it.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ellipsekit {

struct EdgeMapView {
  const std::uint8_t* edge_map;  // non-zero: edge pixel; rows `stride` bytes apart
  std::ptrdiff_t stride;
  const std::int16_t* dx;        // Sobel gradients, rows grad_stride elements apart
  const std::int16_t* dy;
  std::ptrdiff_t grad_stride;
  int width, height;
};

}  // namespace ellipsekit
