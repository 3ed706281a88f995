// Least-squares refinement of a candidate (our addition; the paper stops at eqs. 8-12).
// Direct ellipse-specific fit (Fitzgibbon, Pilu & Fisher 1999) in the numerically stable form of
// Halir & Flusser (1998), on the edge points of the group's arcs, in normalised coordinates.
// The accumulator estimate is quantised (2 degrees, 0.02 in N); the fit uses every point, which
// matters for the small ellipses the Jaccard > 0.8 criterion is hardest on. Measured in README.
// The scatter matrices come from the arcs' moments (point_moments.h): O(1) per group.
#pragma once

#include "ellipsekit/types.h"
#include "fit/arc.h"

namespace ellipsekit {

// Fits the points of arcs[0, count) (their Arc::moments). Returns false (and leaves *out alone)
// when the points do not give an ellipse; keeps out->score.
bool RefineEllipse(const Arc* const* arcs, int count, Ellipse* out);

// Converts A x^2 + B xy + C y^2 + D x + E y + F = 0 to (cx, cy, a, b, theta); false if no ellipse.
bool ConicToEllipse(const double conic[6], Ellipse* out);

}  // namespace ellipsekit
