// The dispatch seam: one table of kernel entry points per backend (rows of kernels/kernels.inc).
// A backend that cannot serve here answers kUnavailable with the reason; Backend::kAuto takes
// the best one that can and reports which one ran.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "ellipsekit/options.h"
#include "ellipsekit/types.h"
#include "kernels/arc_split.h"
#include "kernels/arc_types.h"
#include "kernels/polyline.h"

namespace ellipsekit {

struct KernelTable {
  Backend backend = Backend::kScalar;
  const char* simd_target = "";  // the Highway target of a kSimd table (cpu/simd_kernels.h), else ""
  void (*gaussian)(const std::uint8_t*, std::ptrdiff_t, int, int, std::uint8_t*, std::ptrdiff_t) = nullptr;
  void (*sobel)(const std::uint8_t*, std::ptrdiff_t, int, int, std::int16_t*, std::int16_t*,
                std::uint16_t*, std::ptrdiff_t) = nullptr;
  void (*magnitude_histogram)(const std::uint16_t*, int, int, std::ptrdiff_t, std::uint32_t*) = nullptr;
  void (*nms)(const std::int16_t*, const std::int16_t*, const std::uint16_t*, int, int,
              std::ptrdiff_t, int, int, std::uint8_t*, std::ptrdiff_t) = nullptr;
  void (*hysteresis)(std::uint8_t*, int, int, std::ptrdiff_t, std::int32_t*) = nullptr;
  void (*edge_sign)(const std::uint8_t*, std::ptrdiff_t, const std::int16_t*, const std::int16_t*,
                    std::ptrdiff_t, int, int, std::uint8_t*, std::ptrdiff_t) = nullptr;
  void (*polyline)(const Curves&, std::int32_t, Polylines*, std::vector<std::int32_t>*) = nullptr;
  void (*arc_split)(const Curves&, const Polylines&, std::int64_t, Splits*) = nullptr;
  void (*arc_stats)(const Curves&, const Splits&, int, std::vector<ArcStats>*) = nullptr;
};

const KernelTable& ScalarKernels();

// Resolves options.backend (and, for the SIMD table, options.simd_target) to a table; `why`
// explains a fallback taken by kAuto (empty otherwise).
Status ResolveKernels(const Options& options, const KernelTable** table, std::string* why);

}  // namespace ellipsekit
