#include "fit/arc_index.h"

#include <algorithm>
#include <cmath>

namespace ellipsekit {

void ArcEndIndex::Reserve(int width, int height, std::size_t arcs) {
  const std::size_t cells = static_cast<std::size_t>(width / kCellPx + 2) * (height / kCellPx + 2);
  offset_.reserve(4 * (cells + 1));
  items_.reserve(2 * arcs);
  seen_.reserve(arcs);
}

double ArcEndIndex::EndDistance(const Arc& u, const Arc& v) {
  const double d2 = std::min({(u.p0 - v.p0).squaredNorm(), (u.p0 - v.p1).squaredNorm(),
                              (u.p1 - v.p0).squaredNorm(), (u.p1 - v.p1).squaredNorm()});
  return std::sqrt(d2);
}

void ArcEndIndex::Build(const std::vector<Arc>& arcs) {
  offset_.clear();
  items_.clear();
  // A fresh query count per frame: no stale mark can equal a query of this frame.
  seen_.assign(arcs.size(), 0);
  query_ = 0;
  UniformGrid::Box box;
  for (const Arc& a : arcs) {
    box.Add(a.p0.x(), a.p0.y());
    box.Add(a.p1.x(), a.p1.y());
  }
  grid_.Cover(box, kCellPx);
  if (grid_.cells() == 0) return;
  const int cells = grid_.cells();
  offset_.assign(4 * static_cast<std::size_t>(cells + 1), 0);
  // Count, prefix-sum, fill: an arc whose two ends share a cell is listed there once.
  auto for_each_entry = [&](auto visit) {
    for (int i = 0; i < static_cast<int>(arcs.size()); ++i) {
      const Arc& a = arcs[i];
      const std::size_t base = static_cast<std::size_t>(a.quadrant - 1) * (cells + 1);
      const int c0 = grid_.Cell(a.p0.x(), a.p0.y()), c1 = grid_.Cell(a.p1.x(), a.p1.y());
      visit(base + c0, i);
      if (c1 != c0) visit(base + c1, i);
    }
  };
  for_each_entry([&](std::size_t slot, int) { ++offset_[slot + 1]; });
  for (int q = 0; q < 4; ++q) {
    int* o = offset_.data() + static_cast<std::size_t>(q) * (cells + 1);
    if (q > 0) o[0] = offset_[static_cast<std::size_t>(q) * (cells + 1) - 1];
    for (int c = 0; c < cells; ++c) o[c + 1] += o[c];
  }
  items_.resize(static_cast<std::size_t>(offset_.back()));
  // Fill through a running cursor per cell (the start offsets, advanced), then restore them.
  for_each_entry([&](std::size_t slot, int i) { items_[offset_[slot]++] = i; });
  for (int q = 3; q >= 0; --q) {
    int* o = offset_.data() + static_cast<std::size_t>(q) * (cells + 1);
    for (int c = cells; c > 0; --c) o[c] = o[c - 1];
    o[0] = q > 0 ? offset_[static_cast<std::size_t>(q) * (cells + 1) - 1] : 0;
  }
}

}  // namespace ellipsekit
