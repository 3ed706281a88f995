// Sign classes along the flat stretches of an outline, our addition (Options::flat_stretch_classes).
//
// Eq. 1 gives an edge pixel the class of sign(dx * dy), and curve tracing keeps the classes apart
// (sec. II-A). Where an outline runs nearly level - the near and far apex of a top seen at an
// angle - dx is as small as the noise: on a weak edge (a wooden top against its own side) the
// class flips every 2-3 px over ~25 px around the apex, and the outline falls into pieces shorter
// than T_n that no arc is made of (hard tabletop seed 1: 36 of the 50 wooden tops missed with
// nothing near them have their whole outline in the edge map; docs/flat-apex.md).
//
// This step gives such a stretch the classes of its shape. A stretch is an 8-connected set of
// level edge pixels: gradient within atan(1/3) (18.4 degrees) of vertical. It is looked at when
// two of its pixels side by side in a row have different classes, with a second such pair in the
// same aligned run of 8 pixels of that row (a flicker: changes 2-3 px apart; one change is an apex
// or a junction). When it holds at least kFlatMinPixels pixels and its classes, read along x,
// change at least kFlatMinFlips times (a clean level edge changes once, at its apex), the
// parabola y = a x^2 + b x + c fitted to its pixels (least squares) gives each pixel the class of
// the tangent there: kEdgePlus where dy/dx < 0 (image coordinates, y down: the upper-left and
// lower-right quarters, as eq. 1 gives them), kEdgeMinus elsewhere. The apex becomes the
// stretch's one change of class, where the arcs of two quadrants meet. Edge pixels are neither
// added nor removed.
//
// Measured (`ellipsekit eval DIR [--option flat_stretch_classes=false]`, docs/flat-apex.md):
// the bounds below, the trigger (every pair instead of two in a run of 8: the same gains, the
// step 2.5x the cost), and upright stretches (gradient near horizontal) left alone - with them
// too, hard tabletop seeds 1 / 2 found 5 / 6 fewer tops: on tabletop frames the long upright
// stretches are the sides of cylinders and boxes.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ellipsekit {

// A stretch's gradients: 3 |dx| <= |dy|.
inline constexpr int kFlatAxisRatio = 3;
// Smaller stretches keep their classes: a small ring's apex spans a few pixels.
inline constexpr int kFlatMinPixels = 8;
// Fewer changes of class along x: the edge is clean (two changes lost 2 of su2019_coin's coins).
inline constexpr int kFlatMinFlips = 3;

// edge_map: kEdgeNone / kEdgePlus / kEdgeMinus per pixel (kernels/edge_sign.h), rows `stride`
// bytes apart, reclassified in place; dx, dy: the Sobel gradients, rows grad_stride elements
// apart. queue: room for width * height indices (the detector lends its hysteresis stack).
// Returns the number of pixels whose class changed. Work: one pass over the map, 32 then 8 pixels
// at a time, a flood of the stretches it looks at, a sort and a fit per stretch of
// kFlatMinPixels or more; no allocation.
// Deterministic and integer-exact up to the fit, whose doubles are the same on every backend (the
// step runs on the CPU after every backend's edge stage).
int ClassifyFlatStretches(std::uint8_t* edge_map, std::ptrdiff_t stride, const std::int16_t* dx,
                          const std::int16_t* dy, std::ptrdiff_t grad_stride, int width, int height,
                          std::int32_t* queue);

}  // namespace ellipsekit
