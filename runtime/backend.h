// The dispatch seam: which kernel table (kernels/kernel_table.h) a Detector runs.
// A backend that cannot serve here answers kUnavailable with the reason; Backend::kAuto takes
// the best one that can and reports which one ran.
#pragma once

#include <string>

#include "ellipsekit/options.h"
#include "ellipsekit/types.h"
#include "kernels/kernel_table.h"

namespace ellipsekit {

// Resolves options.backend (and, for the SIMD table, options.simd_target) to a table; `why`
// explains a fallback taken by kAuto (empty otherwise).
Status ResolveKernels(const Options& options, const KernelTable** table, std::string* why);

}  // namespace ellipsekit
