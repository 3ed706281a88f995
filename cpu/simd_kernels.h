// The Highway (SIMD CPU) backend: per-target kernel tables with the same signatures and the same
// exact integer contracts as the scalar references in kernels/<name>.h.
//
// Each compiled-in Highway target (AVX3, AVX2, SSE4, NEON, ..., EMU128) that this CPU supports
// gets its own table of direct function pointers. A Detector picks one when it is created
// (Options::simd_target, else ELLIPSEKIT_HWY_TARGET, else the best), so tests and benchmarks run
// every target in one process, and nothing process-wide is changed by the choice.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/kernel_table.h"

namespace ellipsekit::simd {

using ArcSplitFn = void (*)(const Curves&, const Polylines&, std::int64_t, Splits*);

// One Highway target's kernels.
struct TargetKernels {
  std::int64_t target = 0;  // the HWY_* bit
  const char* name = "";    // Highway's name for it ("AVX3", "AVX2", "SSE4", "EMU128", ...)
  KernelTable table;        // what Backend::kSimd runs on this target
  // The Highway arc_split. Exact, but slower than the reference on typical curves
  // (cpu/arc_split.cc), so `table` keeps the reference; the conformance tests and the bench
  // call this one.
  ArcSplitFn arc_split = nullptr;
};

// Every target compiled in and supported by this CPU, best first (never empty on a CPU Highway
// supports: the EMU128 or SCALAR fallback is always there).
const std::vector<TargetKernels>& Targets();

// The target named `name` (case-insensitive, as TargetKernels::name spells it). An empty name
// means ELLIPSEKIT_HWY_TARGET when that is set and not empty (read on every call), else the best
// target. nullptr, with *why naming the available targets, when the name matches none.
const TargetKernels* FindTarget(const std::string& name, std::string* why);

// The gradient-magnitude histogram and the tiles' maxima: plain C++ (a histogram does not
// vectorise), one copy shared by every target (cpu/canny_thresholds.cc).
void MagnitudeHistogram(const std::uint16_t* mag, int width, int height, std::ptrdiff_t stride,
                        int tile_shift, std::uint32_t* hist, std::uint16_t* tile_max);

}  // namespace ellipsekit::simd
