// polyline: line-segment approximation of each curve (sec. II-B-1, "using [34]").
//
// Ramer-Douglas-Peucker, made exact: for the chord (i, j) the farthest point k maximises
// |cross(p_j - p_i, p_k - p_i)| (first such k on ties); the chord is split at k when
//   16 * cross^2 > tol_q16 * |p_j - p_i|^2,      tol_q16 = round(16 * tolerance^2),
// i.e. when p_k is farther than `tolerance` px from the chord. A segment whose |dx| or |dy|
// exceeds kMaxSegmentComponent is halved (by point index) until it does not, which bounds the
// products of arc_split.h. With coordinates < 2^14 every product fits int64.
// Output: per curve, the increasing point indices of its vertices (first and last point included).
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/arc_types.h"

namespace ellipsekit {

inline constexpr std::int32_t kMaxSegmentComponent = 1024;

struct Polylines {
  std::vector<std::int32_t> vertex;  // global point indices into Curves
  std::vector<std::int32_t> offset;  // curve i: vertex[offset[i] .. offset[i + 1])
  void clear() { vertex.clear(); offset.assign(1, 0); }
};

std::int32_t PolylineToleranceQ16(double tolerance_px);

namespace scalar {
// stack: scratch of at least 2 * (longest curve length) entries.
void Polyline(const Curves& curves, std::int32_t tol_q16, Polylines* out, std::vector<std::int32_t>* stack);
}  // namespace scalar

}  // namespace ellipsekit
