// The kernel table: one entry point per row of kernels/kernels.inc, the seam between the pixel
// stages and whoever provides them (the scalar references here, the Highway tables of cpu/, the
// choice among them in runtime/backend.h). Every table gives bit-identical results.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "ellipsekit/options.h"
#include "ellipsekit/types.h"
#include "kernels/arc_split.h"
#include "kernels/arc_types.h"
#include "kernels/nms.h"
#include "kernels/polyline.h"

namespace ellipsekit {

struct KernelTable {
  Backend backend = Backend::kScalar;
  const char* simd_target = "";  // the Highway target of a kSimd table (cpu/simd_kernels.h), else ""
  void (*gaussian)(const std::uint8_t*, std::ptrdiff_t, int, int, std::uint8_t*, std::ptrdiff_t) = nullptr;
  void (*sobel)(const std::uint8_t*, std::ptrdiff_t, int, int, std::int16_t*, std::int16_t*,
                std::uint16_t*, std::ptrdiff_t) = nullptr;
  void (*magnitude_histogram)(const std::uint16_t*, int, int, std::ptrdiff_t, int, std::uint32_t*,
                              std::uint16_t*) = nullptr;
  void (*nms)(const std::int16_t*, const std::int16_t*, const std::uint16_t*, int, int,
              std::ptrdiff_t, const NmsThresholds&, std::uint8_t*, std::ptrdiff_t) = nullptr;
  void (*hysteresis)(std::uint8_t*, int, int, std::ptrdiff_t, std::int32_t*) = nullptr;
  void (*edge_sign)(const std::uint8_t*, std::ptrdiff_t, const std::int16_t*, const std::int16_t*,
                    std::ptrdiff_t, int, int, std::uint8_t*, std::ptrdiff_t) = nullptr;
  void (*polyline)(const Curves&, std::int32_t, Polylines*, std::vector<std::int32_t>*) = nullptr;
  void (*arc_split)(const Curves&, const Polylines&, std::int64_t, Splits*) = nullptr;
  void (*arc_stats)(const Curves&, const Splits&, int, std::vector<ArcStats>*) = nullptr;
};

// The scalar references (kernels/<name>.h).
const KernelTable& ScalarKernels();

}  // namespace ellipsekit
