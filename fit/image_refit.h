// Refit to the full-resolution image, our addition (issue 18's coarse-to-fine path): an ellipse
// found on level L of the image pyramid (runtime/detector_pyramid.cc) is mapped up 2^L times, so
// its error grows with the level, and the full-resolution frame has no edge map to refit it to
// (computing one is the cost the pyramid saves). Instead the gray image is read along the
// outline's normals: on each of up to kImageRefitSamples normals, the strongest step of
// brightness within `reach` px (a difference across 2^L px, averaged over three parallel lines,
// the peak interpolated to a fraction of a pixel) is one point on the rim; the direct least-squares
// fit of those points (conic_refine.h) is the new ellipse, and a second round at a third of the
// reach fits it again. The refit replaces the ellipse only when most normals found a step
// (kImageRefitMinShare of them, both rounds) and it stays close (feature distance, eq. 17, below
// 0.2 b + 2^L px). Bounded work (samples x profile length), no allocation. Measured in
// docs/resolution.md.
#pragma once

#include "ellipsekit/types.h"

namespace ellipsekit {

inline constexpr int kImageRefitSamples = 128;
inline constexpr double kImageRefitMinShare = 0.6;

// Refits *e (in the image's coordinates, found on pyramid level `level` >= 1) to `image` in
// place, keeping its score; false when it was left as it was.
bool RefitToImage(const ImageView& image, int level, Ellipse* e);

}  // namespace ellipsekit
