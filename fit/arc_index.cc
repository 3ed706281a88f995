#include "fit/arc_index.h"

#include <algorithm>

namespace ellipsekit {

void ArcEndIndex::Reserve(int width, int height, std::size_t arcs) {
  const std::size_t cells = static_cast<std::size_t>(width / kCellPx + 2) * (height / kCellPx + 2);
  offset_.reserve(4 * (cells + 1));
  items_.reserve(2 * arcs);
  seen_.reserve(arcs);
}

int ArcEndIndex::CellOf(const Eigen::Vector2d& p) const {
  const int cx = std::clamp(static_cast<int>((p.x() - origin_x_) / kCellPx), 0, cols_ - 1);
  const int cy = std::clamp(static_cast<int>((p.y() - origin_y_) / kCellPx), 0, rows_ - 1);
  return cy * cols_ + cx;
}

void ArcEndIndex::CellRange(const Eigen::Vector2d& p, double radius, int* x0, int* y0, int* x1, int* y1) const {
  // Clamped in double first: a huge radius must not overflow the int conversion.
  auto cell = [](double v, int n) { return static_cast<int>(std::clamp(std::floor(v / kCellPx), 0.0, n - 1.0)); };
  *x0 = cell(p.x() - radius - origin_x_, cols_);
  *x1 = cell(p.x() + radius - origin_x_, cols_);
  *y0 = cell(p.y() - radius - origin_y_, rows_);
  *y1 = cell(p.y() + radius - origin_y_, rows_);
}

double ArcEndIndex::EndDistance(const Arc& u, const Arc& v) {
  const double d2 = std::min({(u.p0 - v.p0).squaredNorm(), (u.p0 - v.p1).squaredNorm(),
                              (u.p1 - v.p0).squaredNorm(), (u.p1 - v.p1).squaredNorm()});
  return std::sqrt(d2);
}

void ArcEndIndex::Build(const std::vector<Arc>& arcs) {
  cols_ = rows_ = 0;
  offset_.clear();
  items_.clear();
  // A fresh query count per frame: no stale mark can equal a query of this frame.
  seen_.assign(arcs.size(), 0);
  query_ = 0;
  if (arcs.empty()) return;
  double x0 = arcs[0].p0.x(), y0 = arcs[0].p0.y(), x1 = x0, y1 = y0;
  for (const Arc& a : arcs) {
    for (const Eigen::Vector2d& p : {a.p0, a.p1}) {
      x0 = std::min(x0, p.x()); x1 = std::max(x1, p.x());
      y0 = std::min(y0, p.y()); y1 = std::max(y1, p.y());
    }
  }
  origin_x_ = x0;
  origin_y_ = y0;
  cols_ = static_cast<int>((x1 - x0) / kCellPx) + 1;
  rows_ = static_cast<int>((y1 - y0) / kCellPx) + 1;
  const int cells = cols_ * rows_;
  offset_.assign(4 * static_cast<std::size_t>(cells + 1), 0);
  // Count, prefix-sum, fill: an arc whose two ends share a cell is listed there once.
  auto for_each_entry = [&](auto visit) {
    for (int i = 0; i < static_cast<int>(arcs.size()); ++i) {
      const Arc& a = arcs[i];
      const std::size_t base = static_cast<std::size_t>(a.quadrant - 1) * (cells + 1);
      const int c0 = CellOf(a.p0), c1 = CellOf(a.p1);
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
