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
// Local contrast (our addition): a dim region of a bright frame (a top in a shadow, a frame lit
// from one side) has outlines under the frame's thresholds. The frame is cut into square tiles of
// 2^shift px (Options::canny_tile); tile t's maximum magnitude on the histogram rows, M[t], lowers
// its thresholds where it is under the frame's contrast Q(995), in proportion, with the frame's
// bounds:
//   high_t   = min(high, max(high * M[t] / Q(995), high / 4, 3 * Q(500)))  when high <= M[t] < Q(995)
//            = high                                                    otherwise
//   low_t    = high_t * low_permille / 1000
// A tile whose maximum is under the frame's high threshold keeps the frame's pair: it holds no
// strong pixel, no start for an edge, under the frame's pair, and lowering it would start edges in
// its noise and texture (measured: 17-39 % more edge pixels for no detection, docs/contrast.md).
// A tile's thresholds are never above the frame's; one tile covering the frame has M >= Q(995),
// so it gets the frame's pair (the classic rule). Nms (kernels/nms.h) reads the pixel's tile's pair.
// Exact: integer only. The histogram and the tiles' maxima are the kernel; each quantile walk is at
// most 2041 steps of scalar code, and a tile's pair a few integer operations.
// shaders/gaussian_sobel_thresholds.comp repeats the three constants below on the device.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "ellipsekit/options.h"
#include "kernels/nms.h"

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
  int contrast = 0;  // Q(995)
  int noise = 0;     // kNoiseFloorFactor * Q(500)
};

// Picks the frame's thresholds from a histogram of kMaxMagnitude + 1 bins (N = the sum of its
// bins); contrast_ref 0: the fixed floor min_high.
CannyThresholds ThresholdsFromHistogram(const std::uint32_t* hist, int high_permille, int low_permille,
                                        int min_high, int contrast_ref);

// The tile shift of Options::canny_tile (0: one tile, else a power of two >= 32).
int CannyTileShift(int canny_tile);

// Tiles of 2^shift px over a width x height frame, along x and in all.
inline int TilesAlong(int length, int shift) { return (length + (1 << shift) - 1) >> shift; }

// A frame's thresholds tile by tile: the scratch the histogram kernel fills (tile_max) and Nms
// reads (view()). Resize allocates only when the tile count grows (first frame of a size).
struct CannyTiles {
  int shift = kNmsOneTileShift;
  int tiles_x = 1;
  CannyThresholds frame;
  std::vector<std::uint16_t> tile_max;
  std::vector<std::int32_t> low, high;
  void Resize(int width, int height, int tile_shift);
  void Resize(int width, int height, const Options& o) { Resize(width, height, CannyTileShift(o.canny_tile)); }
  NmsThresholds view() const { return {shift, tiles_x, low.data(), high.data()}; }
};

// The frame's pair (ThresholdsFromHistogram) and every tile's (the rule above), from the
// histogram and tiles->tile_max as the magnitude_histogram kernel left them.
void SelectThresholds(const std::uint32_t* hist, int high_permille, int low_permille, int min_high,
                      int contrast_ref, CannyTiles* tiles);
// The same with the rule's parameters taken from `o` (canny_high/low_permille, canny_min_high,
// canny_contrast_ref), as the detector runs it.
inline void SelectThresholds(const std::uint32_t* hist, const Options& o, CannyTiles* tiles) {
  SelectThresholds(hist, o.canny_high_permille, o.canny_low_permille, o.canny_min_high, o.canny_contrast_ref, tiles);
}

namespace scalar {
// hist: kMaxMagnitude + 1 bins, overwritten with the counts of rows 0, kHistogramRowStep, ...;
// tile_max: TilesAlong(width, tile_shift) * TilesAlong(height, tile_shift) entries, overwritten with
// each tile's largest magnitude on those rows (every tile holds one: its first row is a multiple of
// 32).
void MagnitudeHistogram(const std::uint16_t* mag, int width, int height, std::ptrdiff_t stride,
                        int tile_shift, std::uint32_t* hist, std::uint16_t* tile_max);
}  // namespace scalar

}  // namespace ellipsekit
