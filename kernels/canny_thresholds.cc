#include "kernels/canny_thresholds.h"

#include <algorithm>

namespace ellipsekit {

namespace {

// Q(permille): the smallest h with 1000 * #{mag <= h} >= permille * count; kMaxMagnitude if none.
int Quantile(const std::uint32_t* hist, std::int64_t count, int permille) {
  const std::int64_t target = static_cast<std::int64_t>(permille) * count;
  std::int64_t below = 0;
  for (int m = 0; m <= kMaxMagnitude; ++m) {
    below += hist[m];
    if (1000 * below >= target) return m;
  }
  return kMaxMagnitude;
}

}  // namespace

CannyThresholds ThresholdsFromHistogram(const std::uint32_t* hist, int high_permille, int low_permille,
                                        int min_high, int contrast_ref) {
  std::int64_t count = 0;
  for (int m = 0; m <= kMaxMagnitude; ++m) count += hist[m];
  CannyThresholds t;
  t.contrast = Quantile(hist, count, kContrastPermille);
  t.noise = kNoiseFloorFactor * Quantile(hist, count, kNoisePermille);
  int floor_high = min_high;
  if (contrast_ref > 0 && t.contrast < contrast_ref)
    floor_high = std::min(min_high, std::max({min_high * t.contrast / contrast_ref, min_high / 4, t.noise}));
  t.high = std::max(Quantile(hist, count, high_permille), floor_high);
  t.low = t.high * low_permille / 1000;
  return t;
}

int CannyTileShift(int canny_tile) {
  if (canny_tile <= 0) return kNmsOneTileShift;
  int shift = kNmsMinTileShift;
  while ((1 << shift) < canny_tile && shift < kNmsOneTileShift) ++shift;
  return shift;
}

void CannyTiles::Resize(int width, int height, int tile_shift) {
  shift = tile_shift;
  tiles_x = TilesAlong(width, shift);
  const std::size_t n = static_cast<std::size_t>(tiles_x) * TilesAlong(height, shift);
  tile_max.resize(n);
  low.resize(n);
  high.resize(n);
}

void SelectThresholds(const std::uint32_t* hist, int high_permille, int low_permille, int min_high,
                      int contrast_ref, CannyTiles* tiles) {
  const CannyThresholds f = ThresholdsFromHistogram(hist, high_permille, low_permille, min_high, contrast_ref);
  tiles->frame = f;
  for (std::size_t t = 0; t < tiles->tile_max.size(); ++t) {
    const int m = tiles->tile_max[t];
    const bool lowered = m < f.contrast && m >= f.high;
    const int high = lowered ? std::min(f.high, std::max({f.high * m / f.contrast, f.high / 4, f.noise})) : f.high;
    tiles->high[t] = high;
    tiles->low[t] = high * low_permille / 1000;
  }
}

namespace scalar {

void MagnitudeHistogram(const std::uint16_t* mag, int width, int height, std::ptrdiff_t stride,
                        int tile_shift, std::uint32_t* hist, std::uint16_t* tile_max) {
  std::fill(hist, hist + kMaxMagnitude + 1, 0u);
  const int tiles_x = TilesAlong(width, tile_shift);
  std::fill(tile_max, tile_max + static_cast<std::size_t>(tiles_x) * TilesAlong(height, tile_shift), 0);
  for (int y = 0; y < height; y += kHistogramRowStep) {
    const std::uint16_t* row = mag + y * stride;
    std::uint16_t* maxima = tile_max + (y >> tile_shift) * tiles_x;
    for (int x = 0; x < width; ++x) {
      ++hist[row[x]];
      maxima[x >> tile_shift] = std::max(maxima[x >> tile_shift], row[x]);
    }
  }
}

}  // namespace scalar
}  // namespace ellipsekit
