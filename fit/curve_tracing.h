// Edge curves by 8-connectivity, one gradient class at a time (sec. II-A).
//
// Pixels are visited in raster order; from each unvisited edge pixel the chain is followed in
// both directions. The first step takes the first unvisited neighbour of the same class in the
// order E, S, W, N, SE, SW, NW, NE; every later step the unvisited same-class neighbour that turns
// least from the step before (ties in that order), so at a junction a rim keeps going straight and
// the other branches become chains of their own. Deterministic: the same EdgeMap always gives the
// same curves in the same order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "kernels/arc_types.h"

namespace ellipsekit {

struct TraceScratch {
  std::vector<std::uint8_t> work;  // (width + 2) x (height + 2): the edge map in a zero border, cleared as visited
  std::vector<std::int32_t> forward, backward;
};

// edge_map: kEdgeNone / kEdgePlus / kEdgeMinus per pixel, rows `stride` bytes apart.
// dx, dy: Sobel gradients, rows grad_stride elements apart. Curves shorter than min_points are
// dropped (T_n). Appends to `out` after clearing it. Returns the number of edge pixels (kept or not).
// short_curves, when not null: set to the number of dropped curves of at least short_min_points
// points (the detector's crowd pass decides with it whether a shorter T_n is worth a second trace).
// skip, when not null: width x height bytes, row-major without padding; edge pixels where it is
// non-zero are left out (the crowd pass: the edges of the ellipses found already).
// short_out, when not null: receives (after clearing) the dropped curves of at least
// short_out_min_points points (the crowd pass: the pieces of small closed outlines).
// Frames are at most 16384 px a side (points are packed in 16 bits per coordinate while traced).
int TraceCurves(const std::uint8_t* edge_map, std::ptrdiff_t stride, const std::int16_t* dx,
                 const std::int16_t* dy, std::ptrdiff_t grad_stride, int width, int height,
                 int min_points, Curves* out, TraceScratch* scratch, int short_min_points = 0,
                 int* short_curves = nullptr, const std::uint8_t* skip = nullptr, Curves* short_out = nullptr,
                 int short_out_min_points = 0);

}  // namespace ellipsekit
