// canny_thresholds, SIMD backend: the gradient-magnitude histogram and the tiles' maxima (contract:
// kernels/canny_thresholds.h; SelectThresholds stays shared scalar code).
//
// A histogram does not vectorise (scatter-increments collide within a vector), so this is plain
// C++ compiled once, not per Highway target. What it fixes is the reference's serial dependency:
// runs of equal magnitudes (flat regions, mostly 0) make every ++hist[m] wait for the previous
// store to the same bin. Four sub-histograms take consecutive pixels in turn, so equal
// neighbours hit different counters; they are summed at the end. Counts are exact (the same
// as the reference's as long as no bin overflows uint32, which the reference shares).
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

#include "cpu/simd_kernels.h"
#include "kernels/canny_thresholds.h"

namespace ellipsekit::simd {

void MagnitudeHistogram(const std::uint16_t* mag, int width, int height, std::ptrdiff_t stride,
                        int tile_shift, std::uint32_t* hist, std::uint16_t* tile_max) {
  constexpr int kBins = kMaxMagnitude + 1;
  // 4 x 2041 x 4 bytes = 32 KiB on the stack; no allocation per frame.
  std::array<std::array<std::uint32_t, kBins>, 4> sub{};
  const int tiles_x = TilesAlong(width, tile_shift);
  std::fill(tile_max, tile_max + static_cast<std::size_t>(tiles_x) * TilesAlong(height, tile_shift), 0);
  for (int y = 0; y < height; y += kHistogramRowStep) {
    const std::uint16_t* row = mag + y * stride;
    // Each tile's maximum: a second pass over the row (in cache), a reduction the compiler vectorises.
    std::uint16_t* maxima = tile_max + (y >> tile_shift) * tiles_x;
    for (int t = 0; t < tiles_x; ++t) {
      const int x0 = t << tile_shift, x1 = std::min(width, (t + 1) << tile_shift);
      maxima[t] = std::max(maxima[t], *std::max_element(row + x0, row + x1));
    }
    int x = 0;
    for (; x + 4 <= width; x += 4) {
      ++sub[0][row[x]];
      ++sub[1][row[x + 1]];
      ++sub[2][row[x + 2]];
      ++sub[3][row[x + 3]];
    }
    for (; x < width; ++x) ++sub[0][row[x]];
  }
  for (int m = 0; m < kBins; ++m) hist[m] = sub[0][m] + sub[1][m] + sub[2][m] + sub[3][m];
}

}  // namespace ellipsekit::simd
