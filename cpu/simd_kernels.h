// The Highway (SIMD CPU) backend: one entry point per edge kernel, with the same signature and
// the same exact integer contract as the scalar reference in kernels/<name>.h. Each entry point
// dispatches at run time (HWY_DYNAMIC_DISPATCH) to the best target compiled in and supported by
// the CPU; cpu/targets.cc lets callers (the runtime, the conformance tests) restrict that choice.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ellipsekit {

struct KernelTable;

// The SIMD kernel table (backend kSimd). Kernels without a SIMD version (hysteresis is a
// sequential flood fill; the arc stage) point at the scalar references. On first use it applies
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
