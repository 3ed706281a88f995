// arc_split: split curves into arcs at turning and inflection points (sec. II-B-1, Algorithm I).
//
// For the polyline v_0 .. v_M of a curve, the turn at interior vertex k is the angle theta_k from
// a = v_k - v_{k-1} to b = v_{k+1} - v_k, carried exactly as the Gaussian integer
//   z_k = conj(a) * b = (a.b, a x b)          (|a|, |b| components <= 1024, so |z| < 2^21)
// For each pair of consecutive interior vertices (k, k + 1):
//   inflection   sign(a x b)_k * sign(a x b)_{k+1} < 0
//                -> split at the middle point index between v_k and v_{k+1}
//   turning      |theta_{k+1} - theta_k| > T_theta, tested exactly on w = z_{k+1} * conj(z_k)
//                (arg w = theta_{k+1} - theta_k when the signs agree):
//                  Re w <= 0  or  2^16 * |Im w| > tan_q16 * Re w,   tan_q16 = round(2^16 tan T_theta)
//                (|Re w|, |Im w| < 2^43; with T_theta in (0, 60] deg, as Options allows,
//                tan_q16 <= 113512 < 2^17, so both sides stay below 2^60 and fit int64 — a
//                larger angle overflows: SplitTanQ16's callers must keep to that range)
//                -> split at whichever of v_k, v_{k+1} turns more (|theta| compared exactly by
//                   the cross product of (Re z, |Im z|))
// No floating point is involved, so every backend makes identical decisions.
// Output: per curve, the sorted split point indices (duplicates removed); the curve's arcs are the
// ranges between consecutive entries of {first point, splits..., last point}, sharing end points.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/arc_types.h"
#include "kernels/polyline.h"

namespace ellipsekit {

struct Splits {
  std::vector<std::int32_t> index;   // global point indices
  std::vector<std::int32_t> offset;  // curve i: index[offset[i] .. offset[i + 1])
  void clear() { index.clear(); offset.assign(1, 0); }
};

std::int64_t SplitTanQ16(double split_angle_deg);

namespace scalar {
void ArcSplit(const Curves& curves, const Polylines& polylines, std::int64_t tan_q16, Splits* out);
}  // namespace scalar

}  // namespace ellipsekit
