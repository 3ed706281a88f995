#include "runtime/backend.h"

#include <cstring>

#include "kernels/arc_stats.h"
#include "kernels/canny_thresholds.h"
#include "kernels/edge_sign.h"
#include "kernels/gaussian.h"
#include "kernels/hysteresis.h"
#include "kernels/nms.h"
#include "kernels/sobel.h"

#ifdef ELLIPSEKIT_HAVE_SIMD
#include "cpu/simd_kernels.h"
#endif

namespace ellipsekit {

const KernelTable& ScalarKernels() {
  static const KernelTable table = [] {
    KernelTable t;
    t.backend = Backend::kScalar;
    t.gaussian = scalar::Gaussian;
    t.sobel = scalar::Sobel;
    t.magnitude_histogram = scalar::MagnitudeHistogram;
    t.nms = scalar::Nms;
    t.hysteresis = scalar::Hysteresis;
    t.edge_sign = scalar::EdgeSign;
    t.polyline = scalar::Polyline;
    t.arc_split = scalar::ArcSplit;
    t.arc_stats = scalar::ArcStatsFromSplits;
    return t;
  }();
  return table;
}

#ifdef ELLIPSEKIT_HAVE_SIMD
namespace {
// Why ELLIPSEKIT_HWY_TARGET could not be honoured (empty when it was, or was not set).
std::string& SimdTargetProblem() {
  static std::string problem;
  return problem;
}
}  // namespace

// Highway kernels for every stage kernel but hysteresis (a sequential flood fill) and arc_split
// (its Highway version is slower, see below), which keep the scalar references. ELLIPSEKIT_HWY_TARGET is read once, when the table is first resolved.
const KernelTable& SimdKernels() {
  static const KernelTable table = [] {
    simd::ForceTargetFromEnv(&SimdTargetProblem());
    KernelTable t = ScalarKernels();
    t.backend = Backend::kSimd;
    t.gaussian = simd::Gaussian;
    t.sobel = simd::Sobel;
    t.magnitude_histogram = simd::MagnitudeHistogram;
    t.nms = simd::Nms;
    t.edge_sign = simd::EdgeSign;
    t.polyline = simd::Polyline;
    // simd::ArcSplit is exact but measured slower than the reference on typical curves (see
    // cpu/arc_split.cc), so the table keeps the faster exact one.
    t.arc_split = scalar::ArcSplit;
    t.arc_stats = simd::ArcStatsFromSplits;
    return t;
  }();
  return table;
}
#endif

Status ResolveKernels(Backend requested, const KernelTable** table, std::string* why) {
  why->clear();
  switch (requested) {
    case Backend::kScalar:
      *table = &ScalarKernels();
      return Status::Ok();
#ifdef ELLIPSEKIT_HAVE_SIMD
    case Backend::kAuto:
      *table = &SimdKernels();
      *why = SimdTargetProblem();  // empty unless ELLIPSEKIT_HWY_TARGET was ignored
      return Status::Ok();
    case Backend::kSimd:
      *table = &SimdKernels();
      if (!SimdTargetProblem().empty()) return {StatusCode::kInvalidArgument, SimdTargetProblem()};
      return Status::Ok();
#else
    case Backend::kAuto:
      *table = &ScalarKernels();
      *why = "SIMD and Vulkan backends are not built in this version; using scalar";
      return Status::Ok();
    case Backend::kSimd:
      return {StatusCode::kUnavailable, "backend 'simd' is not available: the Highway kernels are not built in this version"};
#endif
    case Backend::kVulkan:
#ifdef ELLIPSEKIT_HAVE_VULKAN
      // The Detector runs the edge stage (runtime/vulkan_edge_stage.h) and the arc stage
      // (runtime/vulkan_arc_stage.h: polyline, arc_split, arc_stats) on the device. This table
      // serves the arc stage only where the device cannot: no shaderInt64, or a frame whose curves
      // exceed its storage-buffer range (identical results: the arc kernels are integer-exact).
#ifdef ELLIPSEKIT_HAVE_SIMD
      *table = &SimdKernels();
#else
      *table = &ScalarKernels();
#endif
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
