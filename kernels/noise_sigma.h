// noise_sigma: how noisy a frame is, to decide how much to smooth it before the edges.
//
// Math:   L(x, y) = sum_{i,j in -1..1} k_i k_j src(x+i, y+j),  k = {1, -2, 1} (Immerkaer 1996):
//         zero on any plane, and on white noise of standard deviation s a normal variable of
//         standard deviation 6 s. sigma = median |L| / (6 * 0.6745) over the interior pixels
//         (x, y) = (1 + i step, 1 + j step), step = NoiseSampleStep (at most ~kNoiseSamples),
//         leaving out those whose own value is 0 or 255 (clipped: their noise is cut off).
//         The median, not Immerkaer's mean: edges and texture are a minority of a frame's pixels
//         and move the median little, so a sharp photograph reads 0-1.3 grey levels and the same
//         photograph with noise of standard deviation 4 / 8 added reads 4.2 / 8.2 (docs/noise.md).
// Units:  grey levels (0-255 scale), in steps of 1 / (6 * 0.6745) = 0.247 (|L| is an integer).
// Exact:  an integer histogram, one division at the end; one scalar function that runs on the
//         CPU before every backend's edge stage, so all backends see the same smoothed frame.
// Cost:   at most ~kNoiseSamples samples whatever the frame's size (~35 instructions each); no
//         allocation (|L| is clamped to kNoiseMaxAbsLaplacian: a 1 KiB histogram on the stack).
#pragma once

#include <cstddef>
#include <cstdint>

namespace ellipsekit::scalar {

inline constexpr int kNoiseSamples = 4096;
inline constexpr int kNoiseMaxAbsLaplacian = 255;  // sigma up to 63 grey levels: beyond any threshold

// The sampling grid's step in x and y: ceil(sqrt(interior pixels / kNoiseSamples)), at least 1, so
// at most ~kNoiseSamples samples.
int NoiseSampleStep(int width, int height);

// src: width x height bytes, rows src_stride bytes apart. 0 when width or height < 3 or every
// sample is clipped.
double NoiseSigma(const std::uint8_t* src, std::ptrdiff_t src_stride, int width, int height);

}  // namespace ellipsekit::scalar
