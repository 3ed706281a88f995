// Least-squares refinement of a candidate (our addition; the paper stops at eqs. 8-12).
// Direct ellipse-specific fit (Fitzgibbon, Pilu & Fisher 1999) in the numerically stable form of
// Halir & Flusser (1998), on the edge points of the group's arcs, in normalised coordinates.
// The accumulator estimate is quantised (2 degrees, 0.02 in N); the fit uses every point, which
// matters for the small ellipses the Jaccard > 0.8 criterion is hardest on. Measured in README.
#pragma once

#include <vector>

#include "ellipsekit/types.h"
#include "fit/arc.h"

namespace ellipsekit {

struct RefineScratch {
  std::vector<double> x, y;
  void Reserve();  // for the largest group (3 arcs)
};

// Returns false (and leaves *out alone) when the points do not give an ellipse.
bool RefineEllipse(const Curves& curves, const Arc* const* arcs, int count, RefineScratch* scratch,
                   Ellipse* out);

// Converts A x^2 + B xy + C y^2 + D x + E y + F = 0 to (cx, cy, a, b, theta); false if no ellipse.
bool ConicToEllipse(const double conic[6], Ellipse* out);

}  // namespace ellipsekit
