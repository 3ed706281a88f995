// Input layout (all little-endian, missing bytes read as 0):
//   byte 0      shape selector: low 2 bits pick the size family (small, thin row, thin column,
//               tiny); bit 2 gives a stride smaller than the width; bit 3 a null data pointer;
//               bit 4 a zero/negative size; bit 5 also runs the Vulkan backend (slow: lavapipe)
//   bytes 1-4   width and height seeds (u16 each)
//   byte 5      extra stride padding
//   byte 6      number of option edits that follow (mod 8)
//   3 bytes per option edit: field index, then a signed 16-bit value (raw, may be out of range)
//   the rest    pixels, repeated to fill the frame (all zero when none are left)
// The pixel buffer is allocated to exactly (height - 1) * stride + width bytes, so a read past the
// last pixel of the view is caught by AddressSanitizer.
#include "fuzz/fuzz_detect.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <vector>

#include "ellipsekit/detector.h"

namespace ellipsekit::fuzz {
namespace {

class Reader {
 public:
  Reader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t U8() { return pos_ < size_ ? data_[pos_++] : 0; }
  std::uint16_t U16() {
    const std::uint16_t lo = U8();
    return static_cast<std::uint16_t>(lo | (U8() << 8));
  }
  std::int16_t S16() { return static_cast<std::int16_t>(U16()); }
  const std::uint8_t* rest() const { return data_ + pos_; }
  std::size_t rest_size() const { return pos_ < size_ ? size_ - pos_ : 0; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

[[noreturn]] void Fail(const char* what, const Status& st) {
  std::fprintf(stderr, "fuzz_detect: invariant broken: %s (status %d: %s)\n", what, static_cast<int>(st.code()),
               st.message().c_str());
  std::abort();
}

// Sets one option from a raw value; many of the values are out of range on purpose.
void EditOption(int field, int v, Options* o) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const double d = v / 64.0;  // fractional values for the double fields
  switch (field % 30) {
    case 0: o->gaussian_blur = (v & 1) != 0; break;
    case 1: o->canny_high_permille = v; break;
    case 2: o->canny_low_permille = v; break;
    case 3: o->canny_min_high = v; break;
    case 4: o->min_curve_points = v; break;
    case 5: o->obb_rule = (v & 1) ? ObbRule::kSideRatio : ObbRule::kMinSide; o->obb_threshold = d; break;
    case 6: o->polyline_tolerance = d; break;
    case 7: o->split_angle_deg = d; break;
    case 8: o->center_method = (v & 1) ? CenterMethod::kArcChords : CenterMethod::kLongestChords; break;
    case 9: o->center_distance = d; break;
    case 10: o->mean_shift_bandwidth = d; break;
    case 11: o->distance_ratio = d; break;
    case 12: o->length_ratio = d; break;
    case 13: o->inlier_rule = (v & 1) ? InlierRule::kAlgebraic : InlierRule::kPixel; o->inlier_threshold = d; break;
    case 14: o->circumference_ratio = v / 1000.0; break;
    case 15: o->cluster_rule = (v & 1) ? ClusterRule::kRelative : ClusterRule::kFeatureDistance; break;
    case 16: o->cluster_distance = d; break;
    case 17: o->cluster_relative = v / 1000.0; break;
    case 18: o->cluster_outer_margin = d; break;
    case 19: o->refine_fit = (v & 1) != 0; o->refined_circumference_ratio = (v >> 1) / 1000.0; break;
    case 20: o->max_arcs = v; break;
    case 21: o->max_pairs = v; break;
    case 22: o->max_triplets = v; break;
    case 23: o->max_candidates = v; break;
    case 24: o->max_mean_shift_iterations = v; break;
    case 25: o->max_image_pixels = v; break;
    case 26: {  // a non-finite value into one of the double fields
      double* fields[] = {&o->obb_threshold, &o->polyline_tolerance, &o->split_angle_deg, &o->center_distance,
                          &o->mean_shift_bandwidth, &o->distance_ratio, &o->length_ratio, &o->inlier_threshold,
                          &o->circumference_ratio, &o->cluster_distance, &o->cluster_outer_margin};
      *fields[static_cast<unsigned>(v) % 11] = (v & 0x100) ? inf : ((v & 0x200) ? -inf : nan);
      break;
    }
    case 27: o->backend = static_cast<Backend>(v); break;  // out-of-range enumerators too
    case 28: o->obb_rule = static_cast<ObbRule>(v & 3); break;
    default: o->center_method = static_cast<CenterMethod>(v & 3); break;
  }
}

void CheckResult(const DetectionResult& r, int w, int h, const Options& o) {
  const Status none;
  if (r.num_edge_pixels < 0 || static_cast<long long>(r.num_edge_pixels) > static_cast<long long>(w) * h)
    Fail("num_edge_pixels out of [0, w*h]", none);
  if (r.num_curves < 0 || r.num_arcs < 0 || r.num_candidates < 0) Fail("negative count", none);
  if (r.num_arcs > o.max_arcs) Fail("num_arcs above max_arcs", none);
  if (r.num_candidates > o.max_candidates) Fail("num_candidates above max_candidates", none);
  if (r.ellipses.size() > static_cast<std::size_t>(r.num_candidates)) Fail("more ellipses than candidates", none);
  if (r.caps_hit & ~0x1Fu) Fail("unknown cap flag", none);
  for (const Ellipse& e : r.ellipses) {
    if (!std::isfinite(e.cx) || !std::isfinite(e.cy) || !std::isfinite(e.a) || !std::isfinite(e.b) ||
        !std::isfinite(e.theta) || !std::isfinite(e.score))
      Fail("non-finite ellipse field", none);
    if (!(e.b > 0) || e.a < e.b) Fail("ellipse axes not a >= b > 0", none);
    if (e.theta < -M_PI / 2 - 1e-9 || e.theta >= M_PI / 2 + 1e-9) Fail("theta outside [-pi/2, pi/2)", none);
  }
  const StageTimings& t = r.timings;
  if (!(t.total_ms >= 0) || !(t.edges_ms >= 0)) Fail("negative timing", none);
}

}  // namespace

int DetectOneInput(const std::uint8_t* data, std::size_t size) {
  Reader in(data, size);
  const std::uint8_t shape = in.U8();
  const int ws = in.U16(), hs = in.U16();
  int w = 0, h = 0;
  switch (shape & 3) {
    case 0: w = 1 + ws % 160; h = 1 + hs % 160; break;   // small frames
    case 1: w = 1 + ws % 16400; h = 1 + hs % 3; break;   // thin rows, past the 16384 px limit
    case 2: w = 1 + ws % 3; h = 1 + hs % 16400; break;   // thin columns
    default: w = 1 + ws % 8; h = 1 + hs % 8; break;      // tiny
  }
  if (shape & 0x10) {  // a non-positive size from the seeds
    if (ws & 1) w = -static_cast<int>(ws % 4); else h = -static_cast<int>(hs % 4);
  }
  std::ptrdiff_t stride = static_cast<std::ptrdiff_t>(w) + in.U8() % 17;
  if (shape & 0x04) stride = static_cast<std::ptrdiff_t>(w) - 1 - (ws % 3);

  Options options;
  const int edits = in.U8() % 8;
  for (int i = 0; i < edits; ++i) {
    const int field = in.U8();
    EditOption(field, in.S16(), &options);
  }

  // The pixels: exactly the bytes the view covers, no slack.
  std::vector<std::uint8_t> pixels;
  const bool sane_geometry = w > 0 && h > 0 && stride >= w;
  if (sane_geometry) {
    pixels.resize(static_cast<std::size_t>(h - 1) * static_cast<std::size_t>(stride) + static_cast<std::size_t>(w));
    const std::uint8_t* src = in.rest();
    const std::size_t n = in.rest_size();
    for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = n ? src[i % n] : 0;
  }
  // A heap copy of exactly the right size keeps the buffer end where ASan can see it.
  std::unique_ptr<std::uint8_t[]> buffer;
  if (!pixels.empty()) {
    buffer = std::make_unique<std::uint8_t[]>(pixels.size());
    std::copy(pixels.begin(), pixels.end(), buffer.get());
  }
  ImageView view;
  view.data = (shape & 0x08) ? nullptr : buffer.get();
  if (!sane_geometry && !(shape & 0x08)) view.data = data;  // any non-null pointer; must not be read
  view.width = w;
  view.height = h;
  view.stride = stride;

  const Status options_ok = ValidateOptions(options);
  const Status image_ok = options_ok.ok() ? ValidateImage(view, options) : options_ok;

  std::vector<Backend> backends = {Backend::kScalar, Backend::kSimd, Backend::kAuto};
  // ELLIPSEKIT_FUZZ_NO_VULKAN=1 leaves Vulkan out (for leak-checking runs: see scripts/fuzz.sh).
  static const bool no_vulkan = [] {
    const char* v = std::getenv("ELLIPSEKIT_FUZZ_NO_VULKAN");
    return v != nullptr && v[0] == '1';
  }();
  if ((shape & 0x20) && !no_vulkan) backends.push_back(Backend::kVulkan);
  DetectionResult result;
  for (Backend b : backends) {
    Options o = options;
    if (options.backend == Backend::kScalar || options.backend == Backend::kSimd ||
        options.backend == Backend::kAuto || options.backend == Backend::kVulkan)
      o.backend = b;  // an out-of-range enumerator is kept: it must be refused
    Detector det(o);
    const Status ds = det.status();
    if (!ds.ok()) {
      if (ds.code() == StatusCode::kUnavailable && (b == Backend::kSimd || b == Backend::kVulkan)) continue;
      if (options_ok.ok() && b == Backend::kScalar) Fail("scalar detector refused valid options", ds);
      if (ds.message().empty()) Fail("error status without a message", ds);
      const Status st = det.detect(view, &result);
      if (st.ok()) Fail("detect() ok on a detector whose status is an error", st);
      continue;
    }
    if (!options_ok.ok()) Fail("detector accepted invalid options", options_ok);
    for (int run = 0; run < 2; ++run) {  // the second run reuses the buffers
      const Status st = det.detect(view, &result);
      if (image_ok.ok() && !st.ok() && !(b == Backend::kVulkan && st.code() != StatusCode::kInvalidArgument))
        Fail("detect() refused a valid image", st);
      if (!image_ok.ok()) {
        if (st.ok()) Fail("detect() accepted an invalid image", image_ok);
        if (st.message().empty()) Fail("error status without a message", st);
        break;
      }
      if (st.ok()) CheckResult(result, w, h, o);
    }
  }
  return 0;
}

}  // namespace ellipsekit::fuzz
