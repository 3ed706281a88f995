#include "kernels/noise_sigma.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>

namespace ellipsekit::scalar {

int NoiseSampleStep(int width, int height) {
  const double interior = static_cast<double>(width - 2) * (height - 2);
  return std::max(1, static_cast<int>(std::ceil(std::sqrt(interior / kNoiseSamples))));
}

double NoiseSigma(const std::uint8_t* src, std::ptrdiff_t src_stride, int width, int height) {
  if (width < 3 || height < 3) return 0.0;
  const int step = NoiseSampleStep(width, height);
  std::array<std::uint32_t, kNoiseMaxAbsLaplacian + 1> hist{};
  std::uint64_t samples = 0;
  for (int y = 1; y + 1 < height; y += step) {
    const std::uint8_t* up = src + (y - 1) * src_stride;
    const std::uint8_t* mid = up + src_stride;
    const std::uint8_t* down = mid + src_stride;
    for (int x = 1; x + 1 < width; x += step) {
      // A clipped pixel (0 or 255) has lost its noise: a dark or saturated half of a frame would
      // pull the median to 0.
      if (mid[x] == 0 || mid[x] == 255) continue;
      // [1 -2 1] along each of the three rows, then [1 -2 1] down.
      const int a = up[x - 1] - 2 * up[x] + up[x + 1];
      const int b = mid[x - 1] - 2 * mid[x] + mid[x + 1];
      const int c = down[x - 1] - 2 * down[x] + down[x + 1];
      ++hist[static_cast<std::size_t>(std::min(std::abs(a - 2 * b + c), kNoiseMaxAbsLaplacian))];
      ++samples;
    }
  }
  if (samples == 0) return 0.0;  // every sample clipped
  // The lower median: the smallest value with at least half of the samples at or below it.
  const std::uint64_t half = (samples + 1) / 2;
  std::uint64_t seen = 0;
  int median = 0;
  while (median < kNoiseMaxAbsLaplacian && (seen += hist[static_cast<std::size_t>(median)]) < half) ++median;
  return median / (6.0 * 0.6745);
}

}  // namespace ellipsekit::scalar
