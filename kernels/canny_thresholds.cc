#include "kernels/canny_thresholds.h"

#include <algorithm>

namespace ellipsekit {

CannyThresholds ThresholdsFromHistogram(const std::uint32_t* hist, int high_permille, int low_permille,
                                        int min_high) {
  std::int64_t count = 0;
  for (int m = 0; m <= kMaxMagnitude; ++m) count += hist[m];
  const std::int64_t target = static_cast<std::int64_t>(high_permille) * count;
  std::int64_t below = 0;
  int h = kMaxMagnitude;
  for (int m = 0; m <= kMaxMagnitude; ++m) {
    below += hist[m];
    if (1000 * below >= target) {
      h = m;
      break;
    }
  }
  CannyThresholds t;
  t.high = std::max(h, min_high);
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
