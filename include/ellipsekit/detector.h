// The ellipse detector (Dong et al. 2018, sec. II).
//
//   ellipsekit::Detector det(options);
//   ellipsekit::DetectionResult result;
//   ellipsekit::Status st = det.detect(view, &result);
//
// detect() never throws and never crashes on bad input: it returns a status naming the problem.
// Buffers are sized on the first frame of a given size and reused, so later frames of that size
// do not allocate (the caller keeps `result` across calls so its vector keeps its capacity).
// A Detector is used by one thread at a time; separate detectors run concurrently.
// With Backend::kVulkan (or a Stream over it), destroy it before the process exits, not from a
// static destructor: NVIDIA's Vulkan driver finalises itself in an exit handler, and Vulkan calls
// made after that crash (seen on an H200, driver 580.159).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "ellipsekit/options.h"
#include "ellipsekit/types.h"

namespace ellipsekit {

// Wall time of each stage of the last detect(), milliseconds.
struct StageTimings {
  double edges_ms = 0;     // blur, Sobel, thresholds, NMS, hysteresis, sign classification
  double curves_ms = 0;    // 8-connected curve tracing, T_n / OBB filter
  double arcs_ms = 0;      // polyline, turn angles, split, arc statistics, quadrants
  double fit_ms = 0;       // grouping, centres, parameters, K and psi (eqs. 3-16)
  double validate_ms = 0;  // edge coverage, clustering (eq. 17), outer-rim search
  double total_ms = 0;     // the whole detect(): the stages above, the pyramid reduction, coarser levels
};

// Which caps of Options were hit on the last frame (the result is then partial).
enum CapFlags : unsigned {
  kCapNone = 0,
  kCapArcs = 1u << 0,
  kCapPairs = 1u << 1,
  kCapTriplets = 1u << 2,
  kCapCandidates = 1u << 3,
  kCapMeanShift = 1u << 4,
  kCapRimSearch = 1u << 5,  // the outer-rim search scanned 2 frames' worth of pixels and stopped
  kCapSecondChance = 1u << 6,  // the second chances (Options::rescue_min_coverage) did the same
};
inline constexpr CapFlags kAllCaps[] = {kCapArcs,      kCapPairs,     kCapTriplets,    kCapCandidates,
                                        kCapMeanShift, kCapRimSearch, kCapSecondChance};

// The name of a cap: the Options field that sets it ("max_arcs", ..., "max_mean_shift_iterations"),
// "rim_search_budget" for kCapRimSearch, "second_chance_budget" for kCapSecondChance; "" for
// anything else.
const char* CapName(CapFlags cap);

struct DetectionResult {
  // Best score first within each pass: the working level's ellipses, then what the crowd pass
  // (Options::crowd_min_curve_points) added, then what each coarser level added (coarse_levels).
  std::vector<Ellipse> ellipses;
  StageTimings timings;
  Backend backend = Backend::kScalar;  // the backend that ran (the edge stage's)
  // The backend that ran the arc stage (polyline, arc split, arc statistics). Differs from
  // `backend` only for kVulkan, whose arc stage runs on the CPU kernels (kSimd, or kScalar without
  // SIMD) on a device without shaderInt64 (Detector::backend_note() says so) or for a frame whose
  // curves exceed the device's storage-buffer range. Same results either way (integer-exact).
  Backend arc_backend = Backend::kScalar;
  const char* simd_target = "";        // the Highway target that ran ("AVX2", ...) when backend is kSimd
  unsigned caps_hit = kCapNone;        // CapFlags
  // The working level's noise (kernels/noise_sigma.h, grey levels; 0 when denoise_min_sigma <= 0)
  // and the extra 3x3 binomial passes it asked for before the edges (Options::denoise_min_sigma).
  double noise_sigma = 0;
  int denoise_passes = 0;
  int num_edge_pixels = 0;
  int num_curves = 0;
  int num_arcs = 0;
  // The grouping's work at the working level: its first pass plus the crowd pass when that ran
  // (Options::crowd_min_curve_points), each pass within the caps, so at most twice a cap.
  int num_pairs = 0;       // arc pairs that passed the position test and gave a centre
  int num_triplets = 0;    // triplets examined (Options::max_triplets per pass)
  // Groups that passed K and psi, and the crowd pass's closed outlines it checked
  // (Options::crowd_closed_min_support); Options::max_candidates per pass.
  int num_candidates = 0;
};

class Detector {
 public:
  explicit Detector(const Options& options = Options());
  ~Detector();
  Detector(Detector&&) noexcept;
  Detector& operator=(Detector&&) noexcept;
  Detector(const Detector&) = delete;
  Detector& operator=(const Detector&) = delete;

  // Options are checked here; an invalid set makes every detect() return that error.
  // A moved-from Detector answers every call with an error status (and default options).
  Status status() const;
  const Options& options() const;
  // Why the backend or SIMD target that runs differs from the one asked for (kAuto without SIMD
  // kernels, an ELLIPSEKIT_HWY_TARGET that names no available target, kVulkan's arc stage on the
  // CPU); empty when it does not.
  const std::string& backend_note() const;

  Status detect(const ImageView& image, DetectionResult* result);

 private:
  friend class Stream;  // runs the pixel stage and the back end of a frame apart (stream.h)
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Checks an Options set; names the first bad field.
Status ValidateOptions(const Options& options);
// Checks an image view against the options' size limit; names the problem.
Status ValidateImage(const ImageView& image, const Options& options);

const char* BackendName(Backend backend);
// Parses "auto", "scalar", "simd", "vulkan"; returns false on anything else.
bool ParseBackend(const char* name, Backend* backend);

}  // namespace ellipsekit
