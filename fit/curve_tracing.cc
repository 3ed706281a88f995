#include "fit/curve_tracing.h"

#include <algorithm>

namespace ellipsekit {

namespace {

constexpr int kStepX[8] = {1, 0, -1, 0, 1, -1, -1, 1};
constexpr int kStepY[8] = {0, 1, 0, -1, 1, 1, -1, -1};
constexpr int kStepOctant[8] = {0, 2, 4, 6, 1, 3, 5, 7};  // direction in units of 45 degrees

int TurnOctants(int from, int to) {
  const int d = (kStepOctant[to] - kStepOctant[from] + 8) % 8;
  return d > 4 ? 8 - d : d;
}

// Follows the chain from `start` (already taken) and appends the pixels it reaches. At a
// junction it takes the neighbour that turns least from the last step (ties: the order above),
// so a rim keeps going where texture edges touch it instead of wandering off into them.
void Follow(std::uint8_t* work, int width, int height, std::int32_t start, std::uint8_t cls,
            std::vector<std::int32_t>* chain) {
  std::int32_t cur = start;
  int last = -1;  // index into kStep of the previous move
  for (;;) {
    const int cy = cur / width, cx = cur - cy * width;
    int best = -1, best_turn = 5;
    for (int k = 0; k < 8; ++k) {
      const int nx = cx + kStepX[k], ny = cy + kStepY[k];
      if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
      if (work[ny * width + nx] != cls) continue;
      if (last < 0) { best = k; break; }
      const int turn = TurnOctants(last, k);
      if (turn < best_turn) { best_turn = turn; best = k; }
    }
    if (best < 0) return;
    const std::int32_t next = (cy + kStepY[best]) * width + cx + kStepX[best];
    work[next] = 0;
    chain->push_back(next);
    cur = next;
    last = best;
  }
}

}  // namespace

void TraceCurves(const std::uint8_t* edge_map, std::ptrdiff_t stride, const std::int16_t* dx,
                 const std::int16_t* dy, std::ptrdiff_t grad_stride, int width, int height,
                 int min_points, Curves* out, TraceScratch* scratch) {
  out->clear();
  std::vector<std::uint8_t>& work = scratch->work;
  work.resize(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y) {
    std::copy(edge_map + y * stride, edge_map + y * stride + width, work.begin() + static_cast<std::ptrdiff_t>(y) * width);
  }
  for (std::int32_t p = 0; p < width * height; ++p) {
    const std::uint8_t cls = work[p];
    if (cls == 0) continue;
    work[p] = 0;
    scratch->forward.clear();
    scratch->backward.clear();
    Follow(work.data(), width, height, p, cls, &scratch->forward);
    Follow(work.data(), width, height, p, cls, &scratch->backward);
    const std::size_t n = scratch->forward.size() + scratch->backward.size() + 1;
    if (n < static_cast<std::size_t>(min_points)) continue;
    auto append = [&](std::int32_t idx) {
      const int y = idx / width, x = idx - y * width;
      out->x.push_back(x);
      out->y.push_back(y);
      out->gx.push_back(dx[y * grad_stride + x]);
      out->gy.push_back(dy[y * grad_stride + x]);
    };
    for (auto it = scratch->backward.rbegin(); it != scratch->backward.rend(); ++it) append(*it);
    append(p);
    for (std::int32_t idx : scratch->forward) append(idx);
    out->sign_class.push_back(cls);
    out->offset.push_back(static_cast<std::int32_t>(out->x.size()));
  }
}

}  // namespace ellipsekit
