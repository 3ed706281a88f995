// Ellipse validation (sec. II-D-1, II-D-2).
//   K(tau) = sum_i (m_i + n_i) / (count (A + B))                       eq. 13 (m_i x n_i: arc i's box)
//   psi(tau) = N_B / (N_a + N_b + N_c), N_B = arc points with d < T_d   eq. 16
//   d = |X + Y - 1| (eq. 15, InlierRule::kAlgebraic), or the first-order geometric distance
//       |F| / |grad F| in px with F = X + Y - 1 (InlierRule::kPixel).
#pragma once

#include "ellipsekit/options.h"
#include "ellipsekit/types.h"
#include "fit/arc.h"

namespace ellipsekit {

double LengthRatio(const Arc* const* arcs, int count, const Ellipse& e);

// With min_ratio it may stop after any arc once psi > min_ratio is out of reach, and returns a
// value <= min_ratio then: the same accept/reject decision, less work on rejected groups.
double CircumferenceRatio(const Curves& curves, const Arc* const* arcs, int count, const Ellipse& e,
                          InlierRule rule, double threshold, double min_ratio = -1);

}  // namespace ellipsekit
