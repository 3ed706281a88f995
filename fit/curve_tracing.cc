#include "fit/curve_tracing.h"

#include <algorithm>

#include "fit/edge_map_view.h"

namespace ellipsekit {

namespace {

constexpr int kStepX[8] = {1, 0, -1, 0, 1, -1, -1, 1};
constexpr int kStepY[8] = {0, 1, 0, -1, 1, 1, -1, -1};
constexpr int kStepOctant[8] = {0, 2, 4, 6, 1, 3, 5, 7};  // direction in units of 45 degrees

constexpr int TurnOctants(int from, int to) {
  const int d = (kStepOctant[to] - kStepOctant[from] + 8) % 8;
  return d > 4 ? 8 - d : d;
}

// For each previous move, the eight moves ordered by how far they turn from it (ties: the order
// above), so the first same-class neighbour in this order is the least-turning one.
struct MoveOrder {
  int order[8][8];
  constexpr MoveOrder() : order{} {
    for (int last = 0; last < 8; ++last) {
      int n = 0;
      for (int turn = 0; turn <= 4; ++turn)
        for (int k = 0; k < 8; ++k)
          if (TurnOctants(last, k) == turn) order[last][n++] = k;
    }
  }
};
constexpr MoveOrder kMoveOrder;

// Points are packed as (y << 16) | x: frames are at most 16384 px a side (ellipsekit/options.h).
std::int32_t PackXY(int x, int y) { return (y << 16) | x; }

// The moves in the order they are tried after move `last` (kMoveOrder), with their index steps
// in `work` (index[last][i] = offset of move[last][i]): each neighbour test is one load. Built
// once per frame, for its pitch.
struct OrderedSteps {
  std::ptrdiff_t index[8][8];
  int move[8][8];
};

// Follows the chain from `start` (already taken) and appends the pixels it reaches, packed. At a
// junction it takes the neighbour that turns least from the last step (ties: the order above),
// so a rim keeps going where texture edges touch it instead of wandering off into them.
// `work` has a one-pixel border of zeros, so neighbours need no bounds tests; indices are into
// `work`, offset[k] the index step of move k.
void Follow(std::uint8_t* work, const std::ptrdiff_t* offset, const OrderedSteps& steps, std::int32_t start, int x,
            int y, std::uint8_t cls, std::vector<std::int32_t>* chain) {
  std::int32_t cur = start;
  int best = -1;
  for (int k = 0; k < 8; ++k) {  // the first move: the first neighbour in the fixed order
    if (work[cur + offset[k]] == cls) { best = k; break; }
  }
  std::int32_t packed = PackXY(x, y);
  while (best >= 0) {
    cur = static_cast<std::int32_t>(cur + offset[best]);
    packed += kStepY[best] * (1 << 16) + kStepX[best];  // x + step stays in [0, 16384): no borrow
    work[cur] = 0;
    chain->push_back(packed);
    const int last = best;
    best = -1;
    for (int i = 0; i < 8; ++i) {
      if (work[cur + steps.index[last][i]] == cls) { best = steps.move[last][i]; break; }
    }
  }
}

// True when the 8 neighbours of index p are all zero (p itself already cleared): one branch
// instead of two Follow calls of 8 tests each.
bool IsolatedPixel(const std::uint8_t* work, std::ptrdiff_t pitch, std::int32_t p) {
  const std::uint8_t* above = work + p - pitch - 1;
  const std::uint8_t* below = work + p + pitch - 1;
  return (above[0] | above[1] | above[2] | work[p - 1] | work[p + 1] | below[0] | below[1] | below[2]) == 0;
}

}  // namespace

int TraceCurves(const std::uint8_t* edge_map, std::ptrdiff_t stride, const std::int16_t* dx,
                 const std::int16_t* dy, std::ptrdiff_t grad_stride, int width, int height,
                 int min_points, Curves* out, TraceScratch* scratch, int short_min_points,
                 int* short_curves, const std::uint8_t* skip, Curves* short_out, int short_out_min_points) {
  out->clear();
  if (short_out) short_out->clear();
  int edge_pixels = 0;
  int short_count = 0;
  const std::ptrdiff_t pitch = width + 2;
  std::ptrdiff_t offset[8];
  for (int k = 0; k < 8; ++k) offset[k] = kStepY[k] * pitch + kStepX[k];
  OrderedSteps steps;
  for (int last = 0; last < 8; ++last) {
    for (int i = 0; i < 8; ++i) {
      steps.move[last][i] = kMoveOrder.order[last][i];
      steps.index[last][i] = offset[steps.move[last][i]];
    }
  }
  std::vector<std::uint8_t>& work = scratch->work;
  work.resize(static_cast<std::size_t>(pitch) * (height + 2));
  std::fill(work.begin(), work.begin() + pitch, 0);  // the zero border, then each row between zeros
  for (int y = 0; y < height; ++y) {
    std::uint8_t* row = work.data() + (y + 1) * pitch;
    row[0] = 0;
    std::copy(edge_map + y * stride, edge_map + y * stride + width, row + 1);
    if (skip) {
      const std::uint8_t* skip_row = skip + static_cast<std::ptrdiff_t>(y) * width;
      for (int x = 0; x < width; ++x) row[x + 1] = skip_row[x] ? 0 : row[x + 1];
    }
    row[width + 1] = 0;
  }
  std::fill(work.end() - pitch, work.end(), 0);
  for (int y = 0; y < height; ++y) {
    const std::int32_t row = static_cast<std::int32_t>((y + 1) * pitch + 1);
    // work is only ever cleared, so what lies behind x needs no second look.
    for (int x = FirstNonZeroByte(&work[row], 0, width); x < width; x = FirstNonZeroByte(&work[row], x + 1, width)) {
      const std::int32_t p = row + x;
      const std::uint8_t cls = work[p];
      work[p] = 0;
      // Isolated pixels (much of what Canny leaves in texture): the 3 x 3 block around is empty.
      if (min_points > 1 && IsolatedPixel(work.data(), pitch, p)) {
        ++edge_pixels;
        continue;
      }
      scratch->forward.clear();
      scratch->backward.clear();
      Follow(work.data(), offset, steps, p, x, y, cls, &scratch->forward);
      Follow(work.data(), offset, steps, p, x, y, cls, &scratch->backward);
      const std::size_t n = scratch->forward.size() + scratch->backward.size() + 1;
      edge_pixels += static_cast<int>(n);
      Curves* to = out;
      if (n < static_cast<std::size_t>(min_points)) {
        short_count += n >= static_cast<std::size_t>(short_min_points);
        if (short_out == nullptr || n < static_cast<std::size_t>(short_out_min_points)) continue;
        to = short_out;
      }
      // One resize per curve, then plain stores (4 push_backs per point cost a capacity test each).
      const std::size_t base = to->x.size();
      to->x.resize(base + n);
      to->y.resize(base + n);
      to->gx.resize(base + n);
      to->gy.resize(base + n);
      std::int32_t* ox = to->x.data() + base;
      std::int32_t* oy = to->y.data() + base;
      std::int16_t* ogx = to->gx.data() + base;
      std::int16_t* ogy = to->gy.data() + base;
      std::size_t k = 0;
      auto append = [&](std::int32_t xy) {
        const int py = xy >> 16, px = xy & 0xffff;
        ox[k] = px;
        oy[k] = py;
        ogx[k] = dx[py * grad_stride + px];
        ogy[k] = dy[py * grad_stride + px];
        ++k;
      };
      for (auto it = scratch->backward.rbegin(); it != scratch->backward.rend(); ++it) append(*it);
      append(PackXY(x, y));
      for (const std::int32_t xy : scratch->forward) append(xy);
      to->sign_class.push_back(cls);
      to->offset.push_back(static_cast<std::int32_t>(to->x.size()));
    }
  }
  if (short_curves) *short_curves = short_count;
  return edge_pixels;
}

}  // namespace ellipsekit
