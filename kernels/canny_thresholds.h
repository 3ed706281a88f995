// canny_thresholds: Canny's automatic thresholds from the gradient-magnitude histogram.
//
// The paper (sec. II-A) uses "Canny with autothresholding" without saying which rule; this is
// the classic percentile rule (MATLAB's edge(): a fixed share of pixels is not edge), made
// integer so every backend agrees, on every kHistogramRowStep-th row (rows 0, 4, 8, ...): a
// quarter of the pixels pins a percentile of a whole frame to within a level or two, at a quarter
// of the cost (the histogram was the largest part of the SIMD and Vulkan edge stages; README):
//   hist[m]  = number of pixels with mag == m on rows y % kHistogramRowStep == 0, m in 0..kMaxMagnitude
//   N        = sum of hist = width * HistogramRows(height)
//   Q(p)     = smallest h with 1000 * #{mag <= h} >= p * N  (kMaxMagnitude when none)
//   floor    = min_high                       when contrast_ref == 0 or Q(995) >= contrast_ref,
//            = min(min_high, max(min_high * Q(995) / contrast_ref, min_high / 4, 3 * Q(500)))
//                                             otherwise (integer divisions)
//   high     = max(floor, Q(high_permille))
//   low      = high * low_permille / 1000              (integer division)
// A pixel is a strong edge candidate when mag > high, a weak one when mag > low.
// The floor follows the frame's contrast (our addition): a dim or low-contrast frame, whose
// strongest gradients (Q(995), its outlines') stay under contrast_ref, gets a floor lowered in
// proportion, so its outlines are not cut by a floor set for a frame of full contrast. Never below
// a quarter of min_high, nor below 3 x the median magnitude Q(500): a frame's median gradient is
// its noise and fine texture, and for white noise (after the 3x3 blur) 3 x its median is about its
// 99.9th percentile, so a frame with few outlines on a noisy ground (Q(995) in the noise) does
// not get its noise for edges. Measured in docs/contrast.md.
// Exact: integer only. The histogram is the kernel; each quantile walk (one, or three when Q(900)
// is under min_high) is at most 2041 steps of scalar code. shaders/gaussian_sobel_thresholds.comp
// repeats the three constants below on the device.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ellipsekit {

inline constexpr int kMaxMagnitude = 2040;  // |dx| + |dy| of the 3x3 Sobel on 8-bit input
inline constexpr int kHistogramRowStep = 4;
inline constexpr int kContrastPermille = 995;  // Q(995): the frame's contrast (see above)
inline constexpr int kNoisePermille = 500;     // Q(500): its noise
inline constexpr int kNoiseFloorFactor = 3;

// Rows of a `height`-row frame that the histogram counts.
constexpr int HistogramRows(int height) { return (height + kHistogramRowStep - 1) / kHistogramRowStep; }

struct CannyThresholds {
  int low = 0;
  int high = 0;
};

// Picks the thresholds from a histogram of kMaxMagnitude + 1 bins (N = the sum of its bins);
// contrast_ref 0: the fixed floor min_high.
CannyThresholds ThresholdsFromHistogram(const std::uint32_t* hist, int high_permille, int low_permille,
                                        int min_high, int contrast_ref);

namespace scalar {
// hist: kMaxMagnitude + 1 bins, overwritten with the counts of rows 0, kHistogramRowStep, ...
void MagnitudeHistogram(const std::uint16_t* mag, int width, int height, std::ptrdiff_t stride,
                        std::uint32_t* hist);
}  // namespace scalar

}  // namespace ellipsekit
