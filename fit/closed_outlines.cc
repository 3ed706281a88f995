#include "fit/closed_outlines.h"

#include <algorithm>
#include <cstdlib>

#include "fit/arc.h"
#include "fit/conic_refine.h"
#include "fit/point_moments.h"

namespace ellipsekit {

namespace {

constexpr int kCell = 4;  // px; >= kClosedLinkGap, so joined ends lie in the same or adjacent cells
static_assert(kCell >= kClosedLinkGap);

std::int32_t Root(std::vector<std::int32_t>& parent, std::int32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];  // path halving
    i = parent[i];
  }
  return i;
}

}  // namespace

void ClosedOutlineScratch::Reserve(std::size_t curves, int width, int height) {
  for (auto* v : {&parent, &min_x, &min_y, &max_x, &max_y, &points, &next, &tail, &open_ends}) v->reserve(curves);
  cell_ends.reserve(2 * curves);
  cell_start.reserve(static_cast<std::size_t>((width - 1) / kCell + 1) * ((height - 1) / kCell + 1) + 1);
}

void FitClosedOutlines(const Curves& curves, double max_extent, ClosedOutlineScratch* s, std::vector<Ellipse>* out) {
  out->clear();
  const int n = curves.size();
  if (n == 0) return;
  // Curve i's ends are end 2 i (its first point) and 2 i + 1 (its last).
  auto end_x = [&](int k) { return curves.x[k % 2 == 0 ? curves.offset[k / 2] : curves.offset[k / 2 + 1] - 1]; };
  auto end_y = [&](int k) { return curves.y[k % 2 == 0 ? curves.offset[k / 2] : curves.offset[k / 2 + 1] - 1]; };
  int x0 = end_x(0), y0 = end_y(0), x1 = x0, y1 = y0;
  for (int k = 1; k < 2 * n; ++k) {
    x0 = std::min(x0, end_x(k)), x1 = std::max(x1, end_x(k));
    y0 = std::min(y0, end_y(k)), y1 = std::max(y1, end_y(k));
  }
  const int cols = (x1 - x0) / kCell + 1, rows = (y1 - y0) / kCell + 1;
  auto cell_of = [&](int k) { return (end_y(k) - y0) / kCell * cols + (end_x(k) - x0) / kCell; };
  // The ends by cell (a counting sort): cell c holds cell_ends[cell_start[c], cell_start[c + 1]).
  s->cell_start.assign(static_cast<std::size_t>(cols) * rows + 1, 0);
  for (int k = 0; k < 2 * n; ++k) ++s->cell_start[cell_of(k)];
  for (std::size_t c = 1; c < s->cell_start.size(); ++c) s->cell_start[c] += s->cell_start[c - 1];
  s->cell_ends.resize(2 * static_cast<std::size_t>(n));
  for (int k = 2 * n - 1; k >= 0; --k) s->cell_ends[--s->cell_start[cell_of(k)]] = k;
  s->parent.resize(n);
  for (int i = 0; i < n; ++i) s->parent[i] = i;
  s->open_ends.assign(n, 0);
  for (int k = 0; k < 2 * n; ++k) {
    const int ex = end_x(k), ey = end_y(k);
    bool joined = false;
    const int cx = (ex - x0) / kCell, cy = (ey - y0) / kCell;
    for (int r = std::max(cy - 1, 0); r <= std::min(cy + 1, rows - 1); ++r) {
      for (int c = std::max(cx - 1, 0); c <= std::min(cx + 1, cols - 1); ++c) {
        const int cell = r * cols + c;
        for (int j = s->cell_start[cell]; j < s->cell_start[cell + 1]; ++j) {
          const int other = s->cell_ends[j];
          if (other == k) continue;
          if (std::abs(end_x(other) - ex) > kClosedLinkGap || std::abs(end_y(other) - ey) > kClosedLinkGap) continue;
          joined = true;  // also to its own other end: a curve that closes on itself
          const std::int32_t a = Root(s->parent, k / 2), b = Root(s->parent, other / 2);
          if (a != b) s->parent[std::max(a, b)] = std::min(a, b);
        }
      }
    }
    s->open_ends[k / 2] += !joined;
  }
  // Each group's box and points, kept at its root, and its curves as a list from the root (a
  // root is its group's smallest curve index).
  s->min_x.resize(n), s->min_y.resize(n), s->max_x.resize(n), s->max_y.resize(n), s->points.assign(n, 0);
  s->next.assign(n, -1), s->tail.resize(n);
  for (int i = 0; i < n; ++i) {
    const std::int32_t r = Root(s->parent, i);
    s->parent[i] = r;
    const int b = curves.offset[i], e = curves.offset[i + 1];
    if (r == i) {
      s->min_x[r] = s->max_x[r] = curves.x[b];
      s->min_y[r] = s->max_y[r] = curves.y[b];
      s->tail[r] = r;
    } else {
      s->next[s->tail[r]] = i;
      s->tail[r] = i;
    }
    for (int p = b; p < e; ++p) {
      s->min_x[r] = std::min(s->min_x[r], curves.x[p]), s->max_x[r] = std::max(s->max_x[r], curves.x[p]);
      s->min_y[r] = std::min(s->min_y[r], curves.y[p]), s->max_y[r] = std::max(s->max_y[r], curves.y[p]);
    }
    s->points[r] += e - b;
    if (r != i) s->open_ends[r] += s->open_ends[i];
  }
  // One fit per small group, to the moments of its curves (each about its own first point, summed
  // about the root's).
  Arc group;  // RefineEllipse reads only the moments
  auto moments = [&](int i) {
    const int b = curves.offset[i];
    return MomentsOfPoints(curves.x.data(), curves.y.data(), b, curves.offset[i + 1] - 1, curves.x[b], curves.y[b]);
  };
  for (int r = 0; r < n; ++r) {
    if (s->parent[r] != r || s->open_ends[r] != 0 || s->points[r] < kClosedMinPoints) continue;
    if (s->max_x[r] - s->min_x[r] > max_extent || s->max_y[r] - s->min_y[r] > max_extent) continue;
    group.moments = moments(r);
    for (int i = s->next[r]; i >= 0; i = s->next[i]) AddShiftedMoments(moments(i), &group.moments);
    const Arc* arcs[1] = {&group};
    Ellipse e;
    if (RefineEllipse(arcs, 1, &e)) out->push_back(e);
  }
}

}  // namespace ellipsekit
