// The Highway (SIMD CPU) backend: one entry point per vectorised kernel, with the same signature and
// the same exact integer contract as the scalar reference in kernels/<name>.h. Each entry point
// dispatches at run time (HWY_DYNAMIC_DISPATCH) to the best target compiled in and supported by
// the CPU; cpu/targets.cc lets callers (the runtime, the conformance tests) restrict that choice.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/arc_split.h"
#include "kernels/arc_types.h"
#include "kernels/polyline.h"

namespace ellipsekit {

struct KernelTable;

// The SIMD kernel table (backend kSimd). Hysteresis, a sequential flood fill, has no SIMD
// version, and simd::ArcSplit is slower than its reference on typical curves (cpu/arc_split.cc):
// both entries point at the scalar references. On first use it applies
// the ELLIPSEKIT_HWY_TARGET environment variable (see ForceSimdTargetFromEnv).
const KernelTable& SimdKernels();

namespace simd {

void Gaussian(const std::uint8_t* src, std::ptrdiff_t src_stride, int width, int height,
              std::uint8_t* dst, std::ptrdiff_t dst_stride);

void Sobel(const std::uint8_t* src, std::ptrdiff_t src_stride, int width, int height,
           std::int16_t* dx, std::int16_t* dy, std::uint16_t* mag, std::ptrdiff_t stride);

void MagnitudeHistogram(const std::uint16_t* mag, int width, int height, std::ptrdiff_t stride,
                        std::uint32_t* hist);

void Nms(const std::int16_t* dx, const std::int16_t* dy, const std::uint16_t* mag, int width,
         int height, std::ptrdiff_t stride, int low, int high, std::uint8_t* out,
         std::ptrdiff_t out_stride);

void EdgeSign(const std::uint8_t* edges, std::ptrdiff_t edge_stride, const std::int16_t* dx,
              const std::int16_t* dy, std::ptrdiff_t stride, int width, int height,
              std::uint8_t* out, std::ptrdiff_t out_stride);

// The arc stage (kernels/polyline.h, arc_split.h, arc_stats.h). Coordinates must lie in
// (-2^14, 2^14) (kMaxImageDimension), which the 32-bit lanes of polyline and arc_split rely on.
void Polyline(const Curves& curves, std::int32_t tol_q16, Polylines* out, std::vector<std::int32_t>* stack);

void ArcSplit(const Curves& curves, const Polylines& polylines, std::int64_t tan_q16, Splits* out);

void ArcStatsFromSplits(const Curves& curves, const Splits& splits, int min_points, std::vector<ArcStats>* out);

// Highway targets (HWY_* bits) that were compiled in and that this CPU supports, best first.
// Ignores any restriction made by ForceTarget.
std::vector<std::int64_t> AvailableTargets();

// Highway's name for a target bit ("AVX2", "SSE4", "SCALAR", ...).
std::string TargetName(std::int64_t target);

// The target the dispatcher picks now.
std::int64_t CurrentTarget();

// Restricts dispatch to `target` (one bit from AvailableTargets()); 0 lifts the restriction.
// Process-wide: Highway keeps one chosen target for all dispatched functions.
void ForceTarget(std::int64_t target);

// Reads ELLIPSEKIT_HWY_TARGET (a name as TargetName prints it, case-insensitive) and forces it.
// Unset or empty: no change, returns true. Unknown or not available here: no change, returns
// false and says why in *why (listing the names that are available).
bool ForceTargetFromEnv(std::string* why);

}  // namespace simd
}  // namespace ellipsekit
