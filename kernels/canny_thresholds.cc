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
  const int quantile_high = Quantile(hist, count, high_permille);
  int floor_high = min_high;
  // The floor only matters under min_high: a frame whose Q(high_permille) reaches it skips the rest.
  if (contrast_ref > 0 && quantile_high < min_high) {
    const int contrast = Quantile(hist, count, kContrastPermille);
    if (contrast < contrast_ref) {
      const int noise = kNoiseFloorFactor * Quantile(hist, count, kNoisePermille);
      floor_high = std::min(min_high, std::max({min_high * contrast / contrast_ref, min_high / 4, noise}));
    }
  }
  CannyThresholds t;
  t.high = std::max(quantile_high, floor_high);
  t.low = t.high * low_permille / 1000;
  return t;
}

namespace scalar {

void MagnitudeHistogram(const std::uint16_t* mag, int width, int height, std::ptrdiff_t stride,
                        std::uint32_t* hist) {
  std::fill(hist, hist + kMaxMagnitude + 1, 0u);
  for (int y = 0; y < height; y += kHistogramRowStep) {
    const std::uint16_t* row = mag + y * stride;
    for (int x = 0; x < width; ++x) ++hist[row[x]];
  }
}

}  // namespace scalar
}  // namespace ellipsekit
