// A uniform grid over the bounding box of a frame's points (arc ends, arc mid-points, candidate
// centres): the one geometry behind the per-frame spatial indexes of the grouping and the
// clustering. A point's cell is clamped to the grid, so points and query ranges outside the box
// (or a huge radius) land on its border cells instead of overflowing.
#pragma once

#include <algorithm>
#include <cmath>

namespace ellipsekit {

struct UniformGrid {
  double x0 = 0, y0 = 0, cell = 1;  // origin (the box's corner) and cell side, px
  int cols = 0, rows = 0;           // 0 x 0 until Cover()

  // Accumulates the box before Cover().
  struct Box {
    double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
    void Add(double x, double y) {
      x0 = std::min(x0, x); x1 = std::max(x1, x);
      y0 = std::min(y0, y); y1 = std::max(y1, y);
    }
    bool empty() const { return !(x0 <= x1); }
  };

  // Cells of `cell_px` over the box (none for an empty box).
  void Cover(const Box& box, double cell_px) {
    cols = rows = 0;
    if (box.empty()) return;
    x0 = box.x0;
    y0 = box.y0;
    cell = cell_px;
    cols = static_cast<int>((box.x1 - box.x0) / cell) + 1;
    rows = static_cast<int>((box.y1 - box.y0) / cell) + 1;
  }
  int cells() const { return cols * rows; }
  int Column(double x) const { return Clamp((x - x0) / cell, cols); }
  int Row(double y) const { return Clamp((y - y0) / cell, rows); }
  int Cell(double x, double y) const { return Row(y) * cols + Column(x); }

 private:
  // Clamped in double first: a far point or a huge radius must not overflow the int conversion.
  static int Clamp(double v, int n) { return static_cast<int>(std::clamp(std::floor(v), 0.0, n - 1.0)); }
};

}  // namespace ellipsekit
