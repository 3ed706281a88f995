// The CPU fuzz entry (fuzz_detect_cpu, fuzz_detect_cpu_replay): small frames, no Vulkan, so that
// a run reaches hundreds of inputs per second; drawn frames make arcs, pairs and triplets, so that
// the grouping (fit/grouping.cc) and the validation after it see real-looking work.
//
// Input layout (all little-endian, missing bytes read as 0):
//   byte 0      flags: bit 0 a STRUCTURED frame (drawn from the bytes below) instead of RAW
//               pixels; bit 1 a null data pointer; bit 2 a zero/negative size; bit 3 a stride
//               smaller than the width; bit 4 runs detect() twice on each detector (the second
//               run reuses the buffers and must give the same result)
//   bytes 1-2   width and height seeds: w = 1 + byte 1 % 128, h = 1 + byte 2 % 96
//   byte 3      extra stride padding (mod 17)
//   byte 4      small caps and grouping switches: bits 0-4 set max_arcs, max_pairs, max_triplets,
//               max_candidates, max_mean_shift_iterations (each bit one cap) to 1 + byte 5 % 64;
//               bit 5 pair_candidates off; bit 6 center_method kArcChords; bit 7 refine_fit off
//   byte 5      the small cap value
//   byte 6      number of option edits that follow (mod 8)
//   3 bytes per option edit: field byte f, then a signed 16-bit value v (raw, may be out of
//               range): f < 0xE0 is EditOption(f, v), else EditOptionMore(f - 0xE0, v)
//               (fuzz_common.h); an in-range backend is replaced by the two under test
//   RAW frame   the rest: pixels, repeated to fill the frame and its padding (zero when none)
//   STRUCTURED frame, drawn on a background with anti-aliased edges:
//     3 bytes   background gray; noise amplitude (mod 16, 0: none); number of shapes (mod 13)
//     8 bytes per shape, a filled ellipse or a ring:
//               cx, cy: -8 + (w + 16) * (byte + sub-pixel) / 256 (and the same with h);
//               a, b: 1.5 + (byte % 128) / 2 px (b > a just turns it); theta: byte * pi / 256;
//               gray; ring: low nibble 0 filled, else a ring that wide in half pixels (filled
//               when that leaves no hole), high nibble the edge blur (1 + nibble / 4 px);
//               sub-pixel: low nibble x, high y (/16)
//     byte      grid of dots: rows = bits 0-2, cols = bits 3-5 (none when either is 0); bit 6
//               rings instead of dots; bit 7 every other dot in the inverted gray (a checker)
//     9 bytes   (only with a grid) first dot x, y (as cx, cy without sub-pixel); x pitch, y pitch
//               (3 + byte % 32 px); radius (1 + (byte % 64) / 4 px); shape (b/a = 0.25 + (low
//               nibble) / 20, at most 1; theta = high nibble * pi / 16); gray; shear (each row
//               shifted by (byte - 128) / 32 px, a perspective-like slant); ring width (1 + byte
//               % 16 / 2 px, rings only)
//     the rest  noise: pixel i gets rest[i % n] % (2 * amplitude + 1) - amplitude
// The pixel buffer is allocated to exactly (height - 1) * stride + width bytes, so a read past the
// last pixel of the view is caught by AddressSanitizer.
//
// Environment (read once): ELLIPSEKIT_FUZZ_VERBOSE=1 prints the frame size and the counts and caps
// of each backend's ok result to stderr, before its checks; ELLIPSEKIT_FUZZ_PGM=FILE writes each
// valid frame to FILE (a PGM; the last input's frame remains), to see what a corpus file draws;
// ELLIPSEKIT_FUZZ_FRESH_DETECTORS=1 creates the Detectors per input instead of reusing them (see
// Detectors() below), to tell whether a finding depends on the frames a Detector saw before.
//
// Contract checked on every input, on Backend::kScalar and Backend::kSimd with the same options
// (one Detector per backend per option set, reused across inputs as in real use):
//   - invalid options: both detectors report an error (same code, with a message), and so does
//     detect(); valid options: both detectors are ok (kSimd may be kUnavailable only in a build
//     without Highway);
//   - an invalid image: detect() gives an error on both (same code, with a message); a valid
//     image with valid options: ok on both, CheckResult (fuzz_common.h) on each, the result names
//     the backend that ran;
//   - both backends give identical results: the same ellipses in the same order with every
//     double bit-identical, and the same num_edge_pixels, num_curves, num_arcs, num_pairs,
//     num_triplets, num_candidates and caps_hit; with bit 4, a detector's second run gives what
//     its first gave.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "ellipsekit/detector.h"
#include "fuzz/fuzz_common.h"
#include "fuzz/fuzz_detect.h"

namespace ellipsekit::fuzz {
namespace {

constexpr int kMaxWidth = 128, kMaxHeight = 96;

// The frame drawing gets no coverage instrumentation: its branches say nothing about the detector
// (they would only add noise to the fuzzer's features) and it runs on every pixel.
#if defined(__clang__)
#define ELLIPSEKIT_FUZZ_NO_COVERAGE __attribute__((no_sanitize("coverage")))
#else
#define ELLIPSEKIT_FUZZ_NO_COVERAGE
#endif

// An ellipse to draw: centre, direction of its first axis, inverse squared semi-axes, edge blur,
// and the range of q = (u / a)^2 + (v / b)^2 outside which a pixel is wholly in or out.
struct Outline {
  double cx, cy, c, s, inv_a2, inv_b2, soft;
  double q_in, q_out;  // q <= q_in: coverage 1; q >= q_out: coverage 0
};

Outline MakeOutline(double cx, double cy, double a, double b, double theta, double soft) {
  // The distance to the outline along the ray from the centre is (r / f) |f - 1| >= min(a, b) |f - 1|
  // (f = sqrt(q), r / f between the semi-axes), so past these bounds the ramp is clamped anyway.
  const double band = 0.5 * soft / std::min(a, b);
  const double in = 1 - band;
  return {cx, cy, std::cos(theta), std::sin(theta), 1 / (a * a), 1 / (b * b), soft, in > 0 ? in * in : -1,
          (1 + band) * (1 + band)};
}

// The anti-aliased share of pixel (x, y) inside the ellipse: the signed distance to the outline
// along the ray from the centre, ramped over `soft` px.
ELLIPSEKIT_FUZZ_NO_COVERAGE double Coverage(double x, double y, const Outline& e) {
  const double dx = x - e.cx, dy = y - e.cy;
  const double u = dx * e.c + dy * e.s, v = -dx * e.s + dy * e.c;
  const double q = u * u * e.inv_a2 + v * v * e.inv_b2;
  if (q >= e.q_out) return 0;
  if (q <= e.q_in || q == 0) return 1;
  const double f = std::sqrt(q);
  const double outside = std::sqrt(u * u + v * v) * (1 - 1 / f);  // px, < 0 inside
  return std::clamp(0.5 - outside / e.soft, 0.0, 1.0);
}

// Blends a filled ellipse, or a ring `ring` px wide (0: filled), of gray level `gray` into `canvas`.
ELLIPSEKIT_FUZZ_NO_COVERAGE void DrawEllipse(double cx, double cy, double a, double b, double theta, double ring,
                                             double soft, double gray, int w, int h, std::vector<double>* canvas) {
  const Outline outer = MakeOutline(cx, cy, a, b, theta, soft);
  const bool hollow = ring > 0 && a - ring > 0.5 && b - ring > 0.5;
  const Outline inner = MakeOutline(cx, cy, hollow ? a - ring : a, hollow ? b - ring : b, theta, soft);
  // Each row from the first to the last pixel with q < q_out: q along a row is the quadratic
  // qa dx^2 + qb dx + qc in dx = x - cx.
  const double c = outer.c, s = outer.s;
  const double qa = c * c * outer.inv_a2 + s * s * outer.inv_b2;
  const double ry = std::sqrt(a * a * s * s + b * b * c * c) + soft + 1;  // half the height, blur included
  const int y0 = static_cast<int>(std::max(0.0, std::floor(cy - ry)));
  const int y1 = static_cast<int>(std::min(h - 1.0, std::ceil(cy + ry)));
  for (int y = y0; y <= y1; ++y) {
    const double dy = y - cy;
    const double qb = 2 * dy * c * s * (outer.inv_a2 - outer.inv_b2);
    const double qc = dy * dy * (s * s * outer.inv_a2 + c * c * outer.inv_b2) - outer.q_out;
    const double disc = qb * qb - 4 * qa * qc;
    if (disc < 0) continue;
    const double root = std::sqrt(disc);
    const int x0 = static_cast<int>(std::max(0.0, std::floor(cx + (-qb - root) / (2 * qa))));
    const int x1 = static_cast<int>(std::min(w - 1.0, std::ceil(cx + (-qb + root) / (2 * qa))));
    for (int x = x0; x <= x1; ++x) {
      double k = Coverage(x, y, outer);
      if (k > 0 && hollow) k = std::max(0.0, k - Coverage(x, y, inner));
      if (k <= 0) continue;
      double& p = (*canvas)[static_cast<std::size_t>(y) * w + x];
      p += (gray - p) * k;
    }
  }
}

// The STRUCTURED frame of the layout above, as w x h gray levels in [0, 255].
ELLIPSEKIT_FUZZ_NO_COVERAGE void DrawFrame(Reader* in, int w, int h, std::vector<std::uint8_t>* out) {
  const double background = in->U8();
  const int amplitude = in->U8() % 16;
  const int shapes = in->U8() % 13;
  static std::vector<double> canvas;  // reused: no allocation per input once the largest frame was drawn
  canvas.assign(static_cast<std::size_t>(w) * h, background);
  auto place = [](int byte, double sub, int extent) { return -8 + (extent + 16) * (byte + sub) / 256.0; };
  for (int i = 0; i < shapes; ++i) {
    const int bx = in->U8(), by = in->U8(), ba = in->U8(), bb = in->U8(), bt = in->U8(), gray = in->U8(),
              ring = in->U8(), sub = in->U8();
    const double cx = place(bx, (sub & 15) / 16.0, w), cy = place(by, (sub >> 4) / 16.0, h);
    const double a = 1.5 + (ba % 128) / 2.0, b = 1.5 + (bb % 128) / 2.0;
    DrawEllipse(cx, cy, a, b, bt * M_PI / 256, (ring & 15) / 2.0, 1 + (ring >> 4) / 4.0, gray, w, h, &canvas);
  }
  const int grid = in->U8();
  const int rows = grid & 7, cols = (grid >> 3) & 7;
  if (rows > 0 && cols > 0) {
    const double gx = place(in->U8(), 0, w), gy = place(in->U8(), 0, h);
    const double pitch_x = 3 + in->U8() % 32, pitch_y = 3 + in->U8() % 32;
    const double radius = 1 + (in->U8() % 64) / 4.0;
    const int shape = in->U8();
    const double ratio = std::min(1.0, 0.25 + (shape & 15) / 20.0), theta = (shape >> 4) * M_PI / 16;
    const double gray = in->U8();
    const double shear = (in->U8() - 128) / 32.0;
    const double ring = (grid & 0x40) ? 1 + (in->U8() % 16) / 2.0 : 0;
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) {
        const double g = ((grid & 0x80) && ((r + c) & 1)) ? 255 - gray : gray;
        DrawEllipse(gx + c * pitch_x + r * shear, gy + r * pitch_y, radius, radius * ratio, theta, ring, 1, g, w, h,
                    &canvas);
      }
    }
  }
  const std::uint8_t* noise = in->rest();
  const std::size_t n = in->rest_size();
  out->resize(canvas.size());
  for (std::size_t i = 0; i < canvas.size(); ++i) {
    int v = static_cast<int>(std::lround(canvas[i]));
    if (amplitude > 0 && n > 0) v += noise[i % n] % (2 * amplitude + 1) - amplitude;
    (*out)[i] = static_cast<std::uint8_t>(std::clamp(v, 0, 255));
  }
}

bool SameDouble(double x, double y) {
  std::uint64_t a, b;
  std::memcpy(&a, &x, sizeof a);
  std::memcpy(&b, &y, sizeof b);
  return a == b;
}

// Aborts unless two results are identical: ellipses (bit for bit, same order) and counts.
void CheckSame(const DetectionResult& p, const DetectionResult& q, const char* what) {
  if (p.ellipses.size() != q.ellipses.size()) Fail(what, Status(StatusCode::kInternal, "ellipse counts differ"));
  for (std::size_t i = 0; i < p.ellipses.size(); ++i) {
    const Ellipse& e = p.ellipses[i];
    const Ellipse& f = q.ellipses[i];
    if (!SameDouble(e.cx, f.cx) || !SameDouble(e.cy, f.cy) || !SameDouble(e.a, f.a) || !SameDouble(e.b, f.b) ||
        !SameDouble(e.theta, f.theta) || !SameDouble(e.score, f.score))
      Fail(what, Status(StatusCode::kInternal, "ellipse " + std::to_string(i) + " differs"));
  }
  if (p.num_edge_pixels != q.num_edge_pixels) Fail(what, Status(StatusCode::kInternal, "num_edge_pixels differ"));
  if (p.num_curves != q.num_curves) Fail(what, Status(StatusCode::kInternal, "num_curves differ"));
  if (p.num_arcs != q.num_arcs) Fail(what, Status(StatusCode::kInternal, "num_arcs differ"));
  if (p.num_pairs != q.num_pairs) Fail(what, Status(StatusCode::kInternal, "num_pairs differ"));
  if (p.num_triplets != q.num_triplets) Fail(what, Status(StatusCode::kInternal, "num_triplets differ"));
  if (p.num_candidates != q.num_candidates) Fail(what, Status(StatusCode::kInternal, "num_candidates differ"));
  if (p.caps_hit != q.caps_hit) Fail(what, Status(StatusCode::kInternal, "caps_hit differ"));
}

constexpr Backend kBackends[2] = {Backend::kScalar, Backend::kSimd};

const char* Env(const char* name) {
  const char* v = std::getenv(name);
  return v != nullptr && v[0] != '\0' ? v : nullptr;
}

// The scalar and the SIMD Detector for `options`, decoded from `key` (the input's option bytes),
// with the backend replaced unless it is out of range. Reused across inputs (a Detector keeps its
// buffers across frames, as in real use: creating one per input costs more than detecting on a
// small frame): kCacheSlots option sets, the oldest replaced first. A finding that only shows after
// other inputs replays with them (the replay runs a folder in order through one cache).
// ELLIPSEKIT_FUZZ_FRESH_DETECTORS=1 creates them per input instead.
Detector* const* Detectors(const std::string& key, const Options& options, bool known_backend) {
  constexpr int kCacheSlots = 16;
  struct Slot {
    std::string key;
    std::unique_ptr<Detector> det[2];
    Detector* ptr[2] = {nullptr, nullptr};
  };
  static const bool fresh = Env("ELLIPSEKIT_FUZZ_FRESH_DETECTORS") != nullptr;
  static std::vector<Slot> cache(kCacheSlots);
  static int next = 0;
  if (!fresh) {
    for (Slot& s : cache)
      if (s.ptr[0] != nullptr && s.key == key) return s.ptr;
  }
  Slot* const slot = &cache[next];
  next = (next + 1) % kCacheSlots;
  slot->key = key;
  for (int i = 0; i < 2; ++i) {
    Options o = options;
    if (known_backend) o.backend = kBackends[i];  // an out-of-range enumerator is kept: it must be refused
    slot->det[i].reset();  // before the next one is made: a Detector holds megabytes
    slot->det[i] = std::make_unique<Detector>(o);
    slot->ptr[i] = slot->det[i].get();
  }
  return slot->ptr;
}

void WritePgm(const char* path, const ImageView& v) {
  std::FILE* f = std::fopen(path, "wb");
  if (f == nullptr) return;
  std::fprintf(f, "P5\n%d %d\n255\n", v.width, v.height);
  for (int y = 0; y < v.height; ++y) std::fwrite(v.data + y * v.stride, 1, static_cast<std::size_t>(v.width), f);
  std::fclose(f);
}

}  // namespace

int DetectCpuOneInput(const std::uint8_t* data, std::size_t size) {
  Reader in(data, size);
  const std::uint8_t flags = in.U8();
  const int ws = in.U8(), hs = in.U8();
  int w = 1 + ws % kMaxWidth, h = 1 + hs % kMaxHeight;
  if (flags & 0x04) {  // a non-positive size from the seeds
    if (ws & 1) w = -(ws % 4); else h = -(hs % 4);
  }
  std::ptrdiff_t stride = static_cast<std::ptrdiff_t>(w) + in.U8() % 17;
  if (flags & 0x08) stride = static_cast<std::ptrdiff_t>(w) - 1 - (ws % 3);

  Options options;
  const std::uint8_t* const options_begin = in.rest();
  const int caps = in.U8(), small = 1 + in.U8() % 64;
  if (caps & 0x01) options.max_arcs = small;
  if (caps & 0x02) options.max_pairs = small;
  if (caps & 0x04) options.max_triplets = small;
  if (caps & 0x08) options.max_candidates = small;
  if (caps & 0x10) options.max_mean_shift_iterations = small;
  if (caps & 0x20) options.pair_candidates = false;
  if (caps & 0x40) options.center_method = CenterMethod::kArcChords;
  if (caps & 0x80) options.refine_fit = false;
  const int edits = in.U8() % 8;
  for (int i = 0; i < edits; ++i) {
    const int field = in.U8();
    const int v = in.S16();
    if (field < 0xE0) EditOption(field, v, &options); else EditOptionMore(field - 0xE0, v, &options);
  }
  const std::string options_bytes(reinterpret_cast<const char*>(options_begin),
                                  static_cast<std::size_t>(in.rest() - options_begin));

  // The pixels, with the padding: exactly the bytes the view covers, no slack.
  const bool sane_geometry = w > 0 && h > 0 && stride >= w;
  std::unique_ptr<std::uint8_t[]> buffer;
  std::size_t buffer_size = 0;
  if (sane_geometry) {
    buffer_size = static_cast<std::size_t>(h - 1) * static_cast<std::size_t>(stride) + static_cast<std::size_t>(w);
    buffer = std::make_unique<std::uint8_t[]>(buffer_size);
    if (flags & 0x01) {
      static std::vector<std::uint8_t> frame;
      DrawFrame(&in, w, h, &frame);
      std::fill_n(buffer.get(), buffer_size, static_cast<std::uint8_t>(255 - frame[0]));  // padding
      for (int y = 0; y < h; ++y)
        std::copy_n(frame.data() + static_cast<std::size_t>(y) * w, w, buffer.get() + y * stride);
    } else {
      const std::uint8_t* src = in.rest();
      const std::size_t n = in.rest_size();
      for (std::size_t i = 0; i < buffer_size; ++i) buffer[i] = n ? src[i % n] : 0;
    }
  }
  const ImageView view = FuzzView(buffer.get(), data, (flags & 0x02) != 0, sane_geometry, w, h, stride);

  const Status options_ok = ValidateOptions(options);
  const Status image_ok = options_ok.ok() ? ValidateImage(view, options) : options_ok;
  static const char* const pgm = Env("ELLIPSEKIT_FUZZ_PGM");
  static const bool verbose = Env("ELLIPSEKIT_FUZZ_VERBOSE") != nullptr;
  if (pgm != nullptr && image_ok.ok()) WritePgm(pgm, view);
  const bool known_backend = options.backend == Backend::kScalar || options.backend == Backend::kSimd ||
                             options.backend == Backend::kAuto || options.backend == Backend::kVulkan;

  Detector* const* detectors = Detectors(options_bytes, options, known_backend);
  Status made[2], ran[2];
  // Reused across inputs, as a caller reuses its result (detect() clears it; its vectors keep
  // their capacity, which the no-allocation contract counts on).
  static DetectionResult result[2], again;
  for (int i = 0; i < 2; ++i) {
    Detector& det = *detectors[i];
    const Options& o = det.options();
    made[i] = det.status();
    if (!made[i].ok()) {
#ifndef ELLIPSEKIT_HAVE_SIMD
      if (i == 1 && options_ok.ok() && made[i].code() == StatusCode::kUnavailable) return 0;  // no Highway
#endif
      if (options_ok.ok()) Fail("a detector refused valid options", made[i]);
      if (made[i].message().empty()) Fail("error status without a message", made[i]);
      ran[i] = det.detect(view, &result[i]);
      if (ran[i].ok()) Fail("detect() ok on a detector whose status is an error", ran[i]);
      if (ran[i].code() != made[i].code()) Fail("detect() status differs from the detector's", ran[i]);
      continue;
    }
    if (!options_ok.ok()) Fail("a detector accepted invalid options", options_ok);
    ran[i] = det.detect(view, &result[i]);
    if (!image_ok.ok()) {
      if (ran[i].ok()) Fail("detect() accepted an invalid image", image_ok);
      if (ran[i].message().empty()) Fail("error status without a message", ran[i]);
      continue;
    }
    if (!ran[i].ok()) Fail("detect() refused a valid image", ran[i]);
    if (verbose) {  // before the checks, so that a failing input shows its counts
      const DetectionResult& r = result[i];
      std::fprintf(stderr, "  %s %dx%d stride %td %s: edge px %d, curves %d, arcs %d, pairs %d, triplets %d, "
                   "candidates %d, ellipses %zu, caps 0x%x (max_arcs %d, max_pairs %d, max_triplets %d, "
                   "max_candidates %d)\n", BackendName(kBackends[i]), w, h, stride, (flags & 1) ? "drawn" : "raw",
                   r.num_edge_pixels, r.num_curves, r.num_arcs, r.num_pairs, r.num_triplets, r.num_candidates,
                   r.ellipses.size(), r.caps_hit, o.max_arcs, o.max_pairs, o.max_triplets, o.max_candidates);
    }
    CheckResult(result[i], w, h, o);
    if (result[i].backend != kBackends[i]) Fail("the result names another backend", ran[i]);
    if (flags & 0x10) {
      const Status st = det.detect(view, &again);
      if (!st.ok()) Fail("second detect() refused a valid image", st);
      CheckSame(result[i], again, "a second detect() of the same frame differs from the first");
    }
  }
  if (made[0].code() != made[1].code()) Fail("scalar and SIMD detectors' status codes differ", made[1]);
  if (ran[0].code() != ran[1].code()) Fail("scalar and SIMD detect() status codes differ", ran[1]);
  if (ran[0].ok()) CheckSame(result[0], result[1], "scalar and SIMD results differ");
  return 0;
}

}  // namespace ellipsekit::fuzz
