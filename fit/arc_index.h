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
#include "fit/uniform_grid.h"

namespace ellipsekit {

class ArcEndIndex {
 public:
  static constexpr int kCellPx = 32;

  void Reserve(int width, int height, std::size_t arcs);
  void Build(const std::vector<Arc>& arcs);

  // Smallest distance between an end point of u and one of v, px.
  static double EndDistance(const Arc& u, const Arc& v);

  // Calls fn(j, d) once for each arc j of `quadrant` with an end point within `radius` px of an
  // end point of `arc` (d = EndDistance(arc, arcs[j]) <= radius), in the order of the grid's cells.
  template <class Fn>
  void ForEachNear(const std::vector<Arc>& arcs, const Arc& arc, int quadrant, double radius, Fn fn);

 private:
  UniformGrid grid_;
  std::vector<int> offset_;  // [quadrant - 1][cell], CSR over items_
  std::vector<int> items_;   // arc indices, each arc once per distinct end-point cell
  std::vector<int> seen_;    // per arc: the last query that found it (ForEachNear reports it once)
  int query_ = 0;
};

template <class Fn>
void ArcEndIndex::ForEachNear(const std::vector<Arc>& arcs, const Arc& arc, int quadrant, double radius, Fn fn) {
  if (grid_.cells() == 0) return;
  ++query_;
  const int* offset = offset_.data() + static_cast<std::size_t>(quadrant - 1) * (grid_.cells() + 1);
  for (const Eigen::Vector2d& p : {arc.p0, arc.p1}) {
    const int x0 = grid_.Column(p.x() - radius), x1 = grid_.Column(p.x() + radius);
    const int y0 = grid_.Row(p.y() - radius), y1 = grid_.Row(p.y() + radius);
    for (int cy = y0; cy <= y1; ++cy) {
      for (int cx = x0; cx <= x1; ++cx) {
        const int cell = cy * grid_.cols + cx;
        for (int k = offset[cell]; k < offset[cell + 1]; ++k) {
          const int j = items_[k];
          if (seen_[j] == query_) continue;
          seen_[j] = query_;
          const double d = EndDistance(arc, arcs[j]);
          if (d <= radius) fn(j, d);
        }
      }
    }
  }
}

}  // namespace ellipsekit
