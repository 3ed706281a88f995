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
    // Each tile's maximum: a second pass over the row (in cache) in blocks of 32 px (every tile is
    // a whole number of them), whose fixed trip count the compiler vectorises at -O2; as int16
    // (magnitudes <= kMaxMagnitude), whose max SSE2, the baseline, has.
    std::uint16_t* maxima = tile_max + (y >> tile_shift) * tiles_x;
    constexpr int kBlock = 1 << kNmsMinTileShift;
    int x = 0;
    for (; x + kBlock <= width; x += kBlock) {
      std::int16_t m = 0;
      for (int k = 0; k < kBlock; ++k) m = std::max(m, static_cast<std::int16_t>(row[x + k]));
      maxima[x >> tile_shift] = std::max(maxima[x >> tile_shift], static_cast<std::uint16_t>(m));
    }
    for (; x < width; ++x) maxima[x >> tile_shift] = std::max(maxima[x >> tile_shift], row[x]);
    for (x = 0; x + 4 <= width; x += 4) {
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
