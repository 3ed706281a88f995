#include "fit/curve_tracing.h"

#include <algorithm>
#include <cstring>

namespace ellipsekit {

namespace {

constexpr int kStepX[8] = {1, 0, -1, 0, 1, -1, -1, 1};
constexpr int kStepY[8] = {0, 1, 0, -1, 1, 1, -1, -1};
constexpr int kStepOctant[8] = {0, 2, 4, 6, 1, 3, 5, 7};  // direction in units of 45 degrees

constexpr int TurnOctants(int from, int to) {
  const int d = (kStepOctant[to] - kStepOctant[from] + 8) % 8;
  return d > 4 ? 8 - d : d;
}

struct TurnTable {
  int turn[8][8];
  constexpr TurnTable() : turn{} {
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b) turn[a][b] = TurnOctants(a, b);
  }
};
constexpr TurnTable kTurn;

// Follows the chain from `start` (already taken) and appends the pixels it reaches. At a
// junction it takes the neighbour that turns least from the last step (ties: the order above),
// so a rim keeps going where texture edges touch it instead of wandering off into them.
// `work` has a one-pixel border of zeros (row pitch `pitch`), so neighbours need no bounds tests;
// indices are into `work`.
void Follow(std::uint8_t* work, std::ptrdiff_t pitch, std::int32_t start, std::uint8_t cls,
            std::vector<std::int32_t>* chain) {
  std::ptrdiff_t offset[8];
  for (int k = 0; k < 8; ++k) offset[k] = kStepY[k] * pitch + kStepX[k];
  std::int32_t cur = start;
  int last = -1;  // index into kStep of the previous move
  for (;;) {
    int best = -1, best_turn = 5;
    for (int k = 0; k < 8; ++k) {
      if (work[cur + offset[k]] != cls) continue;
      if (last < 0) { best = k; break; }
      const int turn = kTurn.turn[last][k];
      if (turn < best_turn) { best_turn = turn; best = k; }
    }
    if (best < 0) return;
    const std::int32_t next = static_cast<std::int32_t>(cur + offset[best]);
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
  const std::ptrdiff_t pitch = width + 2;
  std::vector<std::uint8_t>& work = scratch->work;
  work.assign(static_cast<std::size_t>(pitch) * (height + 2), 0);
  for (int y = 0; y < height; ++y) {
    std::copy(edge_map + y * stride, edge_map + y * stride + width, work.begin() + (y + 1) * pitch + 1);
  }
  for (int y = 0; y < height; ++y) {
    const std::int32_t row = static_cast<std::int32_t>((y + 1) * pitch + 1);
    for (int x = 0; x < width; ++x) {
      const std::int32_t p = row + x;
      if ((x & 7) == 0 && x + 8 <= width) {  // edge pixels are sparse: skip empty runs of 8
        std::uint64_t w;
        std::memcpy(&w, &work[p], sizeof w);
        if (w == 0) {
          x += 7;
          continue;
        }
      }
      const std::uint8_t cls = work[p];
      if (cls == 0) continue;
      work[p] = 0;
      scratch->forward.clear();
      scratch->backward.clear();
      Follow(work.data(), pitch, p, cls, &scratch->forward);
      Follow(work.data(), pitch, p, cls, &scratch->backward);
      const std::size_t n = scratch->forward.size() + scratch->backward.size() + 1;
      if (n < static_cast<std::size_t>(min_points)) continue;
      auto append = [&](std::int32_t idx) {
        const int py = static_cast<int>(idx / pitch) - 1, px = static_cast<int>(idx % pitch) - 1;
        out->x.push_back(px);
        out->y.push_back(py);
        out->gx.push_back(dx[py * grad_stride + px]);
        out->gy.push_back(dy[py * grad_stride + px]);
      };
      for (auto it = scratch->backward.rbegin(); it != scratch->backward.rend(); ++it) append(*it);
      append(p);
      for (std::int32_t idx : scratch->forward) append(idx);
      out->sign_class.push_back(cls);
      out->offset.push_back(static_cast<std::int32_t>(out->x.size()));
    }
  }
}

}  // namespace ellipsekit
