#include "runtime/backend.h"

#include <cstring>

#ifdef ELLIPSEKIT_HAVE_SIMD
#include "cpu/simd_kernels.h"
#endif

namespace ellipsekit {

Status ResolveKernels(const Options& options, const KernelTable** table, std::string* why) {
  why->clear();
  const KernelTable* simd_table = nullptr;  // the SIMD table, when this build and CPU have one
#ifdef ELLIPSEKIT_HAVE_SIMD
  std::string problem;
  const simd::TargetKernels* target = simd::FindTarget(options.simd_target, &problem);
  // A misspelt Options::simd_target is an error whatever the backend, so it never goes unnoticed;
  // a bad ELLIPSEKIT_HWY_TARGET only where SIMD was asked for. kAuto and kVulkan (whose arc stage
  // falls back to this table) then take the best target and say why.
  if (target == nullptr && !simd::Targets().empty()) {
    if (!options.simd_target.empty() || options.backend == Backend::kSimd) return {StatusCode::kInvalidArgument, problem};
    target = &simd::Targets().front();
    if (options.backend != Backend::kScalar) *why = problem + "; using " + target->name;
  }
  if (target != nullptr) simd_table = &target->table;
#else
  if (!options.simd_target.empty()) {
    return {StatusCode::kUnavailable, "simd_target " + options.simd_target + ": the Highway kernels are not built in this version"};
  }
#endif
  switch (options.backend) {
    case Backend::kScalar:
      *table = &ScalarKernels();
      return Status::Ok();
    case Backend::kAuto:
      if (simd_table != nullptr) {
        *table = simd_table;
        return Status::Ok();
      }
      *table = &ScalarKernels();
      *why = "no SIMD kernels in this build or for this CPU; using scalar";
      return Status::Ok();
    case Backend::kSimd:
      if (simd_table == nullptr) {
        return {StatusCode::kUnavailable, "backend 'simd' is not available: no Highway kernels in this build or for this CPU"};
      }
      *table = simd_table;
      return Status::Ok();
    case Backend::kVulkan:
#ifdef ELLIPSEKIT_HAVE_VULKAN
      // The Detector runs the edge stage (runtime/vulkan_edge_stage.h) and the arc stage
      // (runtime/vulkan_arc_stage.h: polyline, arc_split, arc_stats) on the device. This table
      // serves the arc stage only where the device cannot: no shaderInt64, or a frame whose curves
      // exceed its storage-buffer range (identical results: the arc kernels are integer-exact).
      *table = simd_table != nullptr ? simd_table : &ScalarKernels();
      return Status::Ok();
#else
      return {StatusCode::kUnavailable, "backend 'vulkan' is not available: this build has no Vulkan support"};
#endif
  }
  return {StatusCode::kInvalidArgument, "unknown backend value"};
}

const char* BackendName(Backend backend) {
  switch (backend) {
    case Backend::kAuto: return "auto";
    case Backend::kScalar: return "scalar";
    case Backend::kSimd: return "simd";
    case Backend::kVulkan: return "vulkan";
  }
  return "unknown";
}

bool ParseBackend(const char* name, Backend* backend) {
  if (name == nullptr) return false;
  const Backend all[] = {Backend::kAuto, Backend::kScalar, Backend::kSimd, Backend::kVulkan};
  for (Backend b : all) {
    if (std::strcmp(name, BackendName(b)) == 0) {
      *backend = b;
      return true;
    }
  }
  return false;
}

}  // namespace ellipsekit
