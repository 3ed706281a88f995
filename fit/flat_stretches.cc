#include "fit/flat_stretches.h"

#include <algorithm>
#include <bit>
#include <cstdlib>
#include <cstring>

#include "kernels/edge_sign.h"

namespace ellipsekit {

namespace {

// Marks a pixel queued (edge classes are 1 and 2); cleared before returning.
constexpr std::uint8_t kQueued = 0x80;

}  // namespace

int ClassifyFlatStretches(std::uint8_t* edge_map, std::ptrdiff_t stride, const std::int16_t* dx,
                          const std::int16_t* dy, std::ptrdiff_t grad_stride, int width, int height,
                          std::int32_t* queue) {
  auto level = [&](int x, int y) {
    const std::ptrdiff_t k = y * grad_stride + x;
    return kFlatAxisRatio * std::abs(static_cast<int>(dx[k])) <= std::abs(static_cast<int>(dy[k]));
  };
  // Pixels are queued packed, (y << 16) | x: frames are at most 16384 px a side (options.h).
  auto at = [&](std::int32_t p) -> std::uint8_t& { return edge_map[(p >> 16) * stride + (p & 0xffff)]; };
  std::int32_t* tail = queue;  // every stretch's pixels, one after another
  int changed = 0;

  // Queues (x, y) when it is an unqueued level edge pixel.
  auto enqueue = [&](int x, int y) {
    std::uint8_t& v = edge_map[y * stride + x];
    if (v != 0 && (v & kQueued) == 0 && level(x, y)) {
      v |= kQueued;
      *tail++ = (y << 16) | x;
    }
  };
  // The stretch of level pixels around (x, y), a level pixel: a breadth-first flood whose queue
  // is its list of pixels; then its classes from its shape when it is a flat stretch.
  auto classify_stretch = [&](int x, int y) {
    std::int32_t* const begin = tail;
    enqueue(x, y);
    for (const std::int32_t* head = begin; head != tail; ++head) {
      const int px = *head & 0xffff, py = *head >> 16;
      if (px >= 1 && py >= 1 && px + 1 < width && py + 1 < height) {
        enqueue(px + 1, py); enqueue(px - 1, py); enqueue(px, py + 1); enqueue(px, py - 1);
        enqueue(px + 1, py + 1); enqueue(px - 1, py + 1); enqueue(px + 1, py - 1); enqueue(px - 1, py - 1);
        continue;
      }
      for (int ny = std::max(py - 1, 0); ny <= std::min(py + 1, height - 1); ++ny) {
        for (int nx = std::max(px - 1, 0); nx <= std::min(px + 1, width - 1); ++nx) enqueue(nx, ny);
      }
    }
    const std::ptrdiff_t n = tail - begin;
    if (n < kFlatMinPixels) return;
    // Along x (then y); the classes' changes in that order.
    std::sort(begin, tail, [](std::int32_t l, std::int32_t r) {
      const int lx = l & 0xffff, rx = r & 0xffff;
      return lx != rx ? lx < rx : l < r;
    });
    int flips = 0;
    for (const std::int32_t* p = begin + 1; p != tail; ++p) flips += (at(*p) & 3) != (at(p[-1]) & 3);
    // A connected set two columns wide has three distinct x: the fit below is determined.
    if (flips < kFlatMinFlips || (tail[-1] & 0xffff) - (*begin & 0xffff) < 2) return;
    // y = a u^2 + b u + c with u = x - mean x: normal equations, Cramer's rule.
    double mean_x = 0;
    for (const std::int32_t* p = begin; p != tail; ++p) mean_x += *p & 0xffff;
    mean_x /= static_cast<double>(n);
    double s1 = 0, s2 = 0, s3 = 0, s4 = 0, t0 = 0, t1 = 0, t2 = 0;
    for (const std::int32_t* p = begin; p != tail; ++p) {
      const double u = (*p & 0xffff) - mean_x, v = *p >> 16, uu = u * u;
      s1 += u; s2 += uu; s3 += uu * u; s4 += uu * uu;
      t0 += v; t1 += u * v; t2 += uu * v;
    }
    const double s0 = static_cast<double>(n);
    auto det3 = [](double a11, double a12, double a13, double a21, double a22, double a23, double a31,
                   double a32, double a33) {
      return a11 * (a22 * a33 - a23 * a32) - a12 * (a21 * a33 - a23 * a31) + a13 * (a21 * a32 - a22 * a31);
    };
    const double d = det3(s4, s3, s2, s3, s2, s1, s2, s1, s0);
    if (!(d > 0)) return;  // positive for three distinct x; not otherwise (rounding)
    const double a = det3(t2, s3, s2, t1, s2, s1, t0, s1, s0) / d;
    const double b = det3(s4, t2, s2, s3, t1, s1, s2, t0, s0) / d;
    for (const std::int32_t* p = begin; p != tail; ++p) {
      const double slope = 2 * a * ((*p & 0xffff) - mean_x) + b;
      const std::uint8_t cls = slope < 0 ? kEdgePlus : kEdgeMinus;
      std::uint8_t& v = at(*p);
      changed += (v & 3) != cls;
      v = cls | kQueued;
    }
  };
  // A stretch is looked at from a pixel that is level and whose right neighbour is level and of
  // the other class, when the aligned run of 8 pixels holding the pair holds a second such pair (a
  // flicker; a stretch of one class has none, and keeps its classes). Eight pixels at a time, as
  // the bytes of a word: classes XOR to 3 exactly where they differ (1 ^ 2; an empty pixel never
  // does).
  constexpr std::uint64_t kOnes = 0x0101010101010101u;
  auto raw = [](const std::uint8_t* p) {  // into a register (an array would go through the stack)
    std::uint64_t w;
    std::memcpy(&w, p, sizeof w);
    return w;
  };
  auto try_pair = [&](int x, int y) {  // (x, y) and (x + 1, y): edge pixels of different classes
    const std::uint8_t v = edge_map[y * stride + x];
    if ((v & kQueued) == 0 && level(x, y) && level(x + 1, y)) classify_stretch(x, y);
  };
  auto try_pairs = [&](std::uint64_t pairs, int x0, int y) {  // low bit of byte k: a pair at x0 + k
    if ((pairs & (pairs - 1)) == 0) return;  // fewer than two: no flicker here
    for (; pairs != 0; pairs &= pairs - 1) try_pair(x0 + std::countr_zero(pairs) / 8, y);
  };
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* row = edge_map + y * stride;
    int x0 = 0;
    while (x0 + 9 <= width) {  // words whose right neighbours lie in the row
      if (x0 + 33 <= width && (raw(row + x0) | raw(row + x0 + 8) | raw(row + x0 + 16) | raw(row + x0 + 24)) == 0) {
        x0 += 32;  // most of a row is empty
        continue;
      }
      for (const int end = std::min(x0 + 32, width - 8); x0 < end; x0 += 8) {
        const std::uint64_t w = raw(row + x0);
        if (w == 0) continue;
        const std::uint64_t v = w ^ raw(row + x0 + 1);  // low bits 3 where the classes differ
        try_pairs(v & (v >> 1) & kOnes, x0, y);
      }
    }
    // The row's last pixels from x0 (at most 7 have a right neighbour): the word ending at the
    // row's end, shifted to start at x0; in a row narrower than 9 px, pixel by pixel.
    std::uint64_t pairs = 0;
    if (width >= 9 && x0 + 1 < width) {
      const std::uint64_t v = raw(row + width - 9) ^ raw(row + width - 8);
      pairs = (v & (v >> 1) & kOnes) >> (8 * (x0 - (width - 9)));
    } else {
      for (int x = x0; x + 1 < width; ++x) {
        if (((row[x] ^ row[x + 1]) & 3) == 3) pairs |= std::uint64_t{1} << (8 * (x - x0));
      }
    }
    try_pairs(pairs, x0, y);
  }
  for (const std::int32_t* p = queue; p != tail; ++p) at(*p) &= static_cast<std::uint8_t>(~kQueued);
  return changed;
}

}  // namespace ellipsekit
