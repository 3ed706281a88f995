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
  // end point of `arc` (d = EndDistance(arc, arcs[j]) <= radius), in no particular order.
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
  auto visit = [&](int k) {
    const int j = items_[k];
    if (seen_[j] == query_) return;
    seen_[j] = query_;
    const double d = EndDistance(arc, arcs[j]);
    if (d <= radius) fn(j, d);
  };
  struct CellRange {
    int x0, x1, y0, y1;
  };
  CellRange range[2];
  long cells_asked = 0;
  for (int e = 0; e < 2; ++e) {
    const Eigen::Vector2d& p = e == 0 ? arc.p0 : arc.p1;
    range[e] = {grid_.Column(p.x() - radius), grid_.Column(p.x() + radius), grid_.Row(p.y() - radius),
                grid_.Row(p.y() + radius)};
    cells_asked += static_cast<long>(range[e].x1 - range[e].x0 + 1) * (range[e].y1 - range[e].y0 + 1);
  }
  // A radius of the frame's size (large arcs, Options::pair_reach) asks for more cells than the
  // quadrant lists arcs: its list is read straight through instead, so a query costs
  // min(cells near the arc, arcs of the quadrant) (prasad 027_0003: the pair searches and their
  // end distances 14 % -> 9 % of detect()'s profile, `perf record`).
  const int first = offset[0], last = offset[grid_.cells()];
  if (cells_asked >= last - first) {
    for (int k = first; k < last; ++k) visit(k);
    return;
  }
  for (const CellRange& r : range) {
    for (int cy = r.y0; cy <= r.y1; ++cy) {
      for (int cx = r.x0; cx <= r.x1; ++cx) {
        const int cell = cy * grid_.cols + cx;
        for (int k = offset[cell]; k < offset[cell + 1]; ++k) visit(k);
      }
    }
  }
}

}  // namespace ellipsekit
