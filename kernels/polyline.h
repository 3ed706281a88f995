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
#include <cstdlib>
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

// The reference farthest-point search of chord (i, j) over k in [k_begin, k_end): the first k
// maximising |cross(p_j - p_i, p_k - p_i)| (int64), or -1 for an empty range; *best receives that
// |cross|, or -1.
inline std::int32_t FarthestPointInRange(const std::int32_t* px, const std::int32_t* py, std::int32_t i,
                                         std::int32_t j, std::int32_t k_begin, std::int32_t k_end,
                                         std::int64_t* best) {
  const std::int64_t cx = px[j] - px[i], cy = py[j] - py[i];
  std::int64_t best_cr = -1;
  std::int32_t best_k = -1;
  for (std::int32_t k = k_begin; k < k_end; ++k) {
    const std::int64_t cr = std::llabs(cx * (py[k] - py[i]) - cy * (px[k] - px[i]));
    if (cr > best_cr) { best_cr = cr; best_k = k; }
  }
  *best = best_cr;
  return best_k;
}

// The split recursion every backend shares (an explicit stack of chords, see the top of this
// file); only the farthest-point search varies. farthest(i, j, &best) is called for chords with
// j - i >= 2 and must return what FarthestPointInRange(px, py, i, j, i + 1, j, &best) returns.
template <class FarthestPoint>
void PolylineWith(const Curves& curves, std::int32_t tol_q16, Polylines* out, std::vector<std::int32_t>* stack,
                  FarthestPoint&& farthest) {
  out->clear();
  const std::int32_t* px = curves.x.data();
  const std::int32_t* py = curves.y.data();
  for (int c = 0; c < curves.size(); ++c) {
    const std::int32_t first = curves.offset[c], last = curves.offset[c + 1] - 1;
    out->vertex.push_back(first);
    if (last > first) {
      stack->clear();
      stack->push_back(first);
      stack->push_back(last);
      while (!stack->empty()) {
        const std::int32_t j = stack->back(); stack->pop_back();
        const std::int32_t i = stack->back(); stack->pop_back();
        const std::int64_t cx = px[j] - px[i], cy = py[j] - py[i];
        std::int64_t best = -1;
        std::int32_t best_k = -1;
        if (j - i >= 2) best_k = farthest(i, j, &best);
        const std::int64_t len2 = cx * cx + cy * cy;
        std::int32_t split = -1;
        if (best_k >= 0 && 16 * best * best > static_cast<std::int64_t>(tol_q16) * len2) {
          split = best_k;
        } else if ((std::llabs(cx) > kMaxSegmentComponent || std::llabs(cy) > kMaxSegmentComponent) && j - i >= 2) {
          split = i + (j - i) / 2;
        }
        if (split >= 0) {
          // Right half below the left half, so vertices come out in increasing order.
          stack->push_back(split); stack->push_back(j);
          stack->push_back(i); stack->push_back(split);
        } else {
          out->vertex.push_back(j);
        }
      }
    }
    out->offset.push_back(static_cast<std::int32_t>(out->vertex.size()));
  }
}

}  // namespace ellipsekit
