// Edge coverage of an ellipse, our addition: the share of its outline that the edge map supports.
// psi (eq. 16) measures how well the group's own arcs fit the ellipse; it cannot see an ellipse
// fitted through three arcs of different objects, whose outline elsewhere crosses no edge. The
// outline is cut into 64 sectors of equal parametric angle; a sector is covered when, at one of
// its 4 sample points, a pixel of the 3x3 neighbourhood is an edge pixel whose gradient is within
// ~26.6 degrees of the ellipse normal there (cos^2 >= 0.8, either sign).
#pragma once

#include "ellipsekit/types.h"
#include "fit/edge_map_view.h"

namespace ellipsekit {

// In [0, 1]. Work: at most 256 samples x 9 pixels, whatever the ellipse; samples outside the
// frame do not cover. With min_share > 0 it stops as soon as min_share is out of reach and returns
// the share found so far (then < min_share): the same accept/reject decision, less work.
double EdgeCoverage(const EdgeMapView& in, const Ellipse& e, double min_share = 0);

}  // namespace ellipsekit
