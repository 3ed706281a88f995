// Which Highway target the SIMD kernels run on: listing, naming and forcing targets, so the
// runtime can honour ELLIPSEKIT_HWY_TARGET and the conformance tests can run every compiled target
// on one machine.
//
// Highway keeps a single process-wide "chosen target" for every HWY_DYNAMIC_DISPATCH; forcing a
// target here therefore affects all dispatched functions of the process (ours and any other
// Highway user's). hwy::SetSupportedTargetsForTest is the 1.0.x way to mock the CPU's target set
// (hwy::DisableTargets cannot re-enable a target once disabled).
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

// The target this copy was compiled for: tells which copy the dispatcher picks.
std::int64_t CompiledTargetImpl() { return HWY_TARGET; }

}  // namespace HWY_NAMESPACE
}  // namespace ellipsekit
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ellipsekit::simd {
namespace {

// The restriction set by ForceTarget (0: none). Highway has no getter for its mock.
std::int64_t g_forced_target = 0;

void ApplyTargets(std::int64_t targets) {
  hwy::SetSupportedTargetsForTest(targets);
  // Re-pick now rather than on the next dispatch, so CurrentTarget() is right at once.
  hwy::GetChosenTarget().Update(hwy::SupportedTargets());
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

HWY_EXPORT(CompiledTargetImpl);

std::vector<std::int64_t> AvailableTargets() {
  if (g_forced_target != 0) hwy::SetSupportedTargetsForTest(0);
  std::vector<std::int64_t> targets = hwy::SupportedAndGeneratedTargets();  // lowest bit (best) first
  if (g_forced_target != 0) ApplyTargets(g_forced_target);
  return targets;
}

std::string TargetName(std::int64_t target) { return hwy::TargetName(target); }

std::int64_t CurrentTarget() { return HWY_DYNAMIC_DISPATCH(CompiledTargetImpl)(); }

void ForceTarget(std::int64_t target) {
  g_forced_target = target;
  ApplyTargets(target);
}

bool ForceTargetFromEnv(std::string* why) {
  why->clear();
  const char* env = std::getenv("ELLIPSEKIT_HWY_TARGET");
  if (env == nullptr || env[0] == '\0') return true;
  const std::string wanted(env);
  std::string names;
  for (std::int64_t t : AvailableTargets()) {
    if (SameNameIgnoringCase(wanted, hwy::TargetName(t))) {
      ForceTarget(t);
      return true;
    }
    names += names.empty() ? "" : ", ";
    names += hwy::TargetName(t);
  }
  *why = "ELLIPSEKIT_HWY_TARGET=" + wanted + " names no Highway target compiled in and supported here (available: " +
         names + ")";
  return false;
}

}  // namespace ellipsekit::simd
#endif  // HWY_ONCE
