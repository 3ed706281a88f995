// Arcs by the grid cell of their end points, one grid per quadrant: "which arcs of quadrant q end
// within r px of this arc's ends" in time proportional to the cells and arcs near it, so grouping
// (fit/grouping.h) looks only at arcs one ellipse could join, however many ellipses a frame holds.
//
// Built once per frame over the bounding box of the arcs' end points (cells of kCellPx px, CSR
// lists). Reserve() sizes every buffer for a frame and arc cap, so Build() allocates nothing after
// the first frame of a size.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include "fit/arc.h"

namespace ellipsekit {

class ArcEndIndex {
 public:
  static constexpr int kCellPx = 32;

  void Reserve(int width, int height, std::size_t arcs);
  void Build(const std::vector<Arc>& arcs);

  // Smallest distance between an end point of u and one of v, px.
  static double EndDistance(const Arc& u, const Arc& v);

  // Calls fn(j) once for each arc j of `quadrant` with an end point within `radius` px of an end
  // point of `arc` (EndDistance(arc, arcs[j]) <= radius), in the order of the grid's cells.
  template <class Fn>
  void ForEachNear(const std::vector<Arc>& arcs, const Arc& arc, int quadrant, double radius, Fn fn);

 private:
  // The cells that a disc of `radius` round p touches, clamped to the grid.
  void CellRange(const Eigen::Vector2d& p, double radius, int* x0, int* y0, int* x1, int* y1) const;
  int CellOf(const Eigen::Vector2d& p) const;

  double origin_x_ = 0, origin_y_ = 0;
  int cols_ = 0, rows_ = 0;
  std::vector<int> offset_;  // [quadrant - 1][cell], CSR over items_
  std::vector<int> items_;   // arc indices, each arc once per distinct end-point cell
  std::vector<int> seen_;    // per arc: the last query that found it (ForEachNear reports it once)
  int query_ = 0;
};

template <class Fn>
void ArcEndIndex::ForEachNear(const std::vector<Arc>& arcs, const Arc& arc, int quadrant, double radius, Fn fn) {
  if (cols_ == 0) return;
  ++query_;
  const int cells = cols_ * rows_;
  const int* offset = offset_.data() + static_cast<std::size_t>(quadrant - 1) * (cells + 1);
  for (const Eigen::Vector2d& p : {arc.p0, arc.p1}) {
    int x0, y0, x1, y1;
    CellRange(p, radius, &x0, &y0, &x1, &y1);
    for (int cy = y0; cy <= y1; ++cy) {
      for (int cx = x0; cx <= x1; ++cx) {
        const int cell = cy * cols_ + cx;
        for (int k = offset[cell]; k < offset[cell + 1]; ++k) {
          const int j = items_[k];
          if (seen_[j] == query_) continue;
          seen_[j] = query_;
          if (EndDistance(arc, arcs[j]) <= radius) fn(j);
        }
      }
    }
  }
}

}  // namespace ellipsekit
