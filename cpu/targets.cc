// The SIMD backend's kernel tables, one per Highway target compiled in and supported by this
// CPU, and the choice of one by name (Options::simd_target, ELLIPSEKIT_HWY_TARGET).
//
// Each table holds direct pointers into one target's copy of the kernels (the per-target
// functions of cpu/<kernel>.cc), so choosing a target changes nothing process-wide: two Detectors
// may run two targets side by side, and no call pays for dispatch. The pointers are taken once,
// through Highway's own dispatch table of TargetKernelsImpl and a local hwy::ChosenTarget that
// maps a target bit to its slot (the global choice is neither read nor changed).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "cpu/targets.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "cpu/simd_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace ellipsekit {
namespace HWY_NAMESPACE {

// Defined once per target in cpu/<kernel>.cc (contracts: kernels/<kernel>.h).
void GaussianImpl(const std::uint8_t* src, std::ptrdiff_t src_stride, int width, int height,
                  std::uint8_t* dst, std::ptrdiff_t dst_stride);
void SobelImpl(const std::uint8_t* src, std::ptrdiff_t src_stride, int width, int height,
               std::int16_t* dx, std::int16_t* dy, std::uint16_t* mag, std::ptrdiff_t stride);
void NmsImpl(const std::int16_t* dx, const std::int16_t* dy, const std::uint16_t* mag, int width,
             int height, std::ptrdiff_t stride, const NmsThresholds& th, std::uint8_t* out,
             std::ptrdiff_t out_stride);
void HysteresisImpl(std::uint8_t* map, int width, int height, std::ptrdiff_t stride,
                    std::int32_t* stack);
void EdgeSignImpl(const std::uint8_t* edges, std::ptrdiff_t edge_stride, const std::int16_t* dx,
                  const std::int16_t* dy, std::ptrdiff_t stride, int width, int height,
                  std::uint8_t* out, std::ptrdiff_t out_stride);
void PolylineImpl(const Curves& curves, std::int32_t tol_q16, Polylines* out, std::vector<std::int32_t>* stack);
void ArcSplitImpl(const Curves& curves, const Polylines& polylines, std::int64_t tan_q16, Splits* out);
void ArcStatsFromSplitsImpl(const Curves& curves, const Splits& splits, int min_points, std::vector<ArcStats>* out);

simd::TargetKernels TargetKernelsImpl() {
  simd::TargetKernels k;
  k.target = HWY_TARGET;
  k.name = hwy::TargetName(HWY_TARGET);
  k.table = ScalarKernels();
  k.table.backend = Backend::kSimd;
  k.table.simd_target = k.name;
  k.table.gaussian = &GaussianImpl;
  k.table.sobel = &SobelImpl;
  k.table.magnitude_histogram = &simd::MagnitudeHistogram;  // plain C++, one copy for all targets
  k.table.nms = &NmsImpl;
  k.table.hysteresis = &HysteresisImpl;
  k.table.edge_sign = &EdgeSignImpl;
  k.table.polyline = &PolylineImpl;
  k.table.arc_stats = &ArcStatsFromSplitsImpl;
  // The Highway arc_split is exact but slower than the reference on typical curves
  // (cpu/arc_split.cc), so the table keeps the reference and the Highway one rides along for the
  // conformance tests and the bench.
  k.arc_split = &ArcSplitImpl;
  return k;
}

}  // namespace HWY_NAMESPACE
}  // namespace ellipsekit
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ellipsekit::simd {
namespace {

HWY_EXPORT(TargetKernelsImpl);

TargetKernels KernelsOf(std::int64_t target) {
#if (HWY_TARGETS & (HWY_TARGETS - 1)) == 0
  (void)target;  // one target compiled: HWY_EXPORT's table has a single slot
  return HWY_STATIC_DISPATCH(TargetKernelsImpl)();
#else
  hwy::ChosenTarget slot;  // a local one: maps `target` to its slot of the table
  slot.Update(target);
  return HWY_DISPATCH_TABLE(TargetKernelsImpl)[slot.GetIndex()]();
#endif
}

bool SameNameIgnoringCase(const std::string& a, const char* b) {
  std::size_t i = 0;
  for (; i < a.size() && b[i] != '\0'; ++i) {
    if (std::toupper(static_cast<unsigned char>(a[i])) != std::toupper(static_cast<unsigned char>(b[i]))) {
      return false;
    }
  }
  return i == a.size() && b[i] == '\0';
}

}  // namespace

const std::vector<TargetKernels>& Targets() {
  static const std::vector<TargetKernels> targets = [] {
    std::vector<TargetKernels> v;
    for (std::int64_t t : hwy::SupportedAndGeneratedTargets()) {  // lowest bit (best) first
      TargetKernels k = KernelsOf(t);
      if (k.target == t) v.push_back(k);  // always, unless Highway's slot mapping changed
    }
    return v;
  }();
  return targets;
}

const TargetKernels* FindTarget(const std::string& requested, std::string* why) {
  why->clear();
  std::string name = requested;
  const char* env = std::getenv("ELLIPSEKIT_HWY_TARGET");
  const bool from_env = name.empty() && env != nullptr && env[0] != '\0';
  if (from_env) name = env;
  const std::vector<TargetKernels>& all = Targets();
  if (all.empty()) {
    *why = "no Highway target is supported on this CPU";
    return nullptr;
  }
  if (name.empty()) return &all.front();
  std::string names;
  for (const TargetKernels& k : all) {
    if (SameNameIgnoringCase(name, k.name)) return &k;
    names += names.empty() ? "" : ", ";
    names += k.name;
  }
  *why = std::string(from_env ? "ELLIPSEKIT_HWY_TARGET=" : "simd_target ") + name +
         " names no Highway target compiled in and supported here (available: " + names + ")";
  return nullptr;
}

}  // namespace ellipsekit::simd
#endif  // HWY_ONCE
