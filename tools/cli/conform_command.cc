// ellipsekit conform: run every stage of every backend on real images and count how far each
// one is from the scalar reference (kernels/*.h).
//
// Each stage is fed the scalar reference's output of the stage before it, so a difference points
// at that stage alone; the arc stage runs on the curves traced (and OBB-filtered, as the Detector
// does) from the scalar edge map; "ellipses" compares whole Detector runs. Output planes have
// padded rows and a guard row filled with a sentinel, so a kernel writing outside its region
// shows up as differing elements too.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "ellipsekit/detector.h"
#include "fit/arc_selection.h"
#include "fit/curve_tracing.h"
#include "kernels/arc_stats.h"
#include "kernels/canny_thresholds.h"
#include "runtime/backend.h"
#include "tools/cli/args.h"
#include "tools/cli/commands.h"
#include "tools/cli/image_io.h"
#ifdef ELLIPSEKIT_HAVE_SIMD
#include "cpu/simd_kernels.h"
#endif
#ifdef ELLIPSEKIT_HAVE_VULKAN
#include "runtime/vulkan_arc_stage.h"
#include "runtime/vulkan_edge_stage.h"
#endif

namespace ellipsekit::cli {

const char kConformUsage[] =
    "Usage: ellipsekit conform [options] IMAGE...\n"
    "\n"
    "Runs each stage of each backend on each image and prints how many pixels or decisions differ\n"
    "from the scalar reference. Each stage gets the reference's output of the stage before it;\n"
    "the arc stage runs on the curves traced from the reference edge map.\n"
    "\n"
    "Options:\n"
    "  --backends LIST   comma-separated from scalar, simd, vulkan (default: all available here;\n"
    "                    scalar checks the reference against a second run of itself)\n"
    "  --targets T       best (default): simd on the target a Detector picks (ELLIPSEKIT_HWY_TARGET,\n"
    "                    else the best one here);\n"
    "                    all: simd once per Highway target compiled in and supported here\n"
    "  -h, --help        this text\n"
    "\n"
    "Output: one line per image, backend and stage:\n"
    "  conform <image> <backend>[:<target>] <stage> <number differing>\n"
    "stages (CPU backends): gaussian (blurred bytes), sobel (pixels with dx, dy or mag differing),\n"
    "  thresholds (of low, high), nms (map), hysteresis (map), edge_sign (edge map),\n"
    "  polyline (vertex and offset elements), arc_split (split index and offset elements),\n"
    "  arc_stats (fields of the per-arc records), ellipses (Detector results differing in any field).\n"
    "vulkan: sobel (pixels with dx or dy differing), edge_sign (edge map), then the device arc stage\n"
    "  (polyline, arc_split, arc_stats chained in one submit on the reference curves; the CPU table\n"
    "  when the device lacks shaderInt64, said on stderr), and ellipses. Row padding counts: writes\n"
    "  outside the image differ.\n"
    "Last line: conform: N comparisons, M differing\n"
    "Exit status: 0 all identical, 1 something differs, an image could not be read or a backend\n"
    "asked for is unavailable (reported on stderr), 2 bad usage.\n";

namespace {

constexpr int kPad = 16;               // extra elements per output row
constexpr std::uint8_t kSentinel = 0xA5;

enum class Which { kScalar, kSimd, kVulkan };

const char* WhichName(Which w) {
  switch (w) {
    case Which::kScalar: return "scalar";
    case Which::kSimd: return "simd";
    case Which::kVulkan: return "vulkan";
  }
  return "?";
}

struct ConformArgs {
  std::vector<Which> backends;
  bool backends_given = false;
  bool all_targets = false;
  std::vector<std::string> images;
};

ConformArgs ParseConformArgs(const std::vector<std::string>& argv, bool* help) {
  ConformArgs a;
  ArgReader r(argv);
  while (r.Next()) {
    if (!r.IsFlag()) {
      a.images.push_back(r.positional());
      continue;
    }
    const std::string& name = r.name();
    if (name == "--help" || name == "-h") {
      *help = true;
      return a;
    } else if (name == "--backends") {
      const std::string v = r.Value();
      a.backends.clear();
      a.backends_given = true;
      std::size_t start = 0;
      while (true) {
        const std::size_t comma = v.find(',', start);
        const std::string item = v.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        Which w;
        if (item == "scalar") {
          w = Which::kScalar;
        } else if (item == "simd") {
          w = Which::kSimd;
        } else if (item == "vulkan") {
          w = Which::kVulkan;
        } else {
          throw UsageError(name + ": unknown backend '" + item + "': expected scalar, simd or vulkan");
        }
        if (std::find(a.backends.begin(), a.backends.end(), w) == a.backends.end()) a.backends.push_back(w);
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
    } else if (name == "--targets") {
      const std::string v = r.Value();
      if (v != "all" && v != "best") throw UsageError(name + ": bad value '" + v + "': expected all or best");
      a.all_targets = v == "all";
    } else {
      throw UsageError("unknown option '" + name + "'");
    }
  }
  if (a.images.empty()) throw UsageError("no image given");
  if (!a.backends_given) a.backends = {Which::kScalar, Which::kSimd, Which::kVulkan};
  return a;
}

// An output plane: height rows of `stride` elements plus one guard row, sentinel-filled.
template <class T>
struct Plane {
  int width = 0, height = 0;
  std::ptrdiff_t stride = 0;
  std::vector<T> v;

  Plane() = default;
  Plane(int w, int h) : width(w), height(h), stride(w + kPad) {
    T fill;
    std::memset(&fill, kSentinel, sizeof(T));
    v.assign(static_cast<std::size_t>(stride) * (h + 1), fill);
  }
  T* data() { return v.data(); }
  const T* data() const { return v.data(); }
};

template <class T>
std::int64_t CountDiff(const std::vector<T>& a, const std::vector<T>& b) {
  const std::size_t n = std::min(a.size(), b.size());
  std::int64_t d = static_cast<std::int64_t>(std::max(a.size(), b.size()) - n);
  for (std::size_t i = 0; i < n; ++i) d += a[i] != b[i];
  return d;
}

// The CPU edge stage's intermediate results on one image.
struct EdgeStage {
  Plane<std::uint8_t> blurred;
  Plane<std::int16_t> dx, dy;
  Plane<std::uint16_t> mag;
  CannyTiles th;  // the frame's pair and every tile's
  Plane<std::uint8_t> nms, hyst, edges;
};

struct ArcStage {
  Polylines polylines;
  Splits splits;
  std::vector<ArcStats> stats;
};

// The scalar reference: every stage chained, plus the curves the arc stage works on.
struct Reference {
  EdgeStage e;
  Curves curves;
  ArcStage arcs;
  DetectionResult result;
};

void RunEdgeChain(const KernelTable& k, const ImageView& img, const Options& o, EdgeStage* e) {
  const int w = img.width, h = img.height;
  e->blurred = Plane<std::uint8_t>(w, h);
  k.gaussian(img.data, img.stride, w, h, e->blurred.data(), e->blurred.stride);
  const std::uint8_t* src = o.gaussian_blur ? e->blurred.data() : img.data;
  const std::ptrdiff_t src_stride = o.gaussian_blur ? e->blurred.stride : img.stride;
  e->dx = Plane<std::int16_t>(w, h);
  e->dy = Plane<std::int16_t>(w, h);
  e->mag = Plane<std::uint16_t>(w, h);
  k.sobel(src, src_stride, w, h, e->dx.data(), e->dy.data(), e->mag.data(), e->dx.stride);
  std::vector<std::uint32_t> hist(kMaxMagnitude + 1);
  e->th.Resize(w, h, o);
  k.magnitude_histogram(e->mag.data(), w, h, e->mag.stride, e->th.shift, hist.data(), e->th.tile_max.data());
  SelectThresholds(hist.data(), o, &e->th);
  e->nms = Plane<std::uint8_t>(w, h);
  k.nms(e->dx.data(), e->dy.data(), e->mag.data(), w, h, e->dx.stride, e->th.view(), e->nms.data(), e->nms.stride);
  e->hyst = e->nms;
  std::vector<std::int32_t> stack(static_cast<std::size_t>(w) * h);
  k.hysteresis(e->hyst.data(), w, h, e->hyst.stride, stack.data());
  e->edges = Plane<std::uint8_t>(w, h);
  k.edge_sign(e->hyst.data(), e->hyst.stride, e->dx.data(), e->dy.data(), e->dx.stride, w, h, e->edges.data(),
              e->edges.stride);
}

int CountArcStatsDiff(const std::vector<ArcStats>& a, const std::vector<ArcStats>& b) {
  constexpr int kFields = 19;
  const std::size_t n = std::min(a.size(), b.size());
  int d = static_cast<int>(std::max(a.size(), b.size()) - n) * kFields;
  for (std::size_t i = 0; i < n; ++i) {
    const ArcStats& p = a[i];
    const ArcStats& q = b[i];
    d += (p.curve != q.curve) + (p.begin != q.begin) + (p.end != q.end) + (p.x0 != q.x0) + (p.y0 != q.y0) +
         (p.x1 != q.x1) + (p.y1 != q.y1) + (p.xm != q.xm) + (p.ym != q.ym) + (p.min_x != q.min_x) +
         (p.min_y != q.min_y) + (p.max_x != q.max_x) + (p.max_y != q.max_y) + (p.g0x != q.g0x) +
         (p.g0y != q.g0y) + (p.g1x != q.g1x) + (p.g1y != q.g1y) + (p.quadrant != q.quadrant) +
         (p.sign_class != q.sign_class);
  }
  return d;
}

bool SameDouble(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

// Ellipses (by rank) that are missing on one side or differ in any field, bit for bit.
int CountEllipseDiff(const std::vector<Ellipse>& a, const std::vector<Ellipse>& b) {
  const std::size_t n = std::min(a.size(), b.size());
  int d = static_cast<int>(std::max(a.size(), b.size()) - n);
  for (std::size_t i = 0; i < n; ++i) {
    const Ellipse& p = a[i];
    const Ellipse& q = b[i];
    d += !(SameDouble(p.cx, q.cx) && SameDouble(p.cy, q.cy) && SameDouble(p.a, q.a) && SameDouble(p.b, q.b) &&
           SameDouble(p.theta, q.theta) && SameDouble(p.score, q.score));
  }
  return d;
}

class Reporter {
 public:
  void Line(const std::string& image, const std::string& backend, const char* stage, std::int64_t n) {
    std::printf("conform %s %s %s %lld\n", image.c_str(), backend.c_str(), stage, static_cast<long long>(n));
    ++comparisons_;
    differing_ += n != 0;
  }
  void Summary() const {
    std::printf("conform: %lld comparisons, %lld differing\n", comparisons_, differing_);
    std::fflush(stdout);
  }
  bool any_differ() const { return differing_ != 0; }

 private:
  long long comparisons_ = 0, differing_ = 0;
};

// One CPU kernel table against the reference, stage by stage, each fed the reference's inputs.
void CompareTable(const KernelTable& k, const ImageView& img, const Options& o, const Reference& ref,
                  const std::string& image, const std::string& label, Reporter* rep) {
  const int w = img.width, h = img.height;
  const EdgeStage& r = ref.e;

  Plane<std::uint8_t> blurred(w, h);
  k.gaussian(img.data, img.stride, w, h, blurred.data(), blurred.stride);
  rep->Line(image, label, "gaussian", CountDiff(blurred.v, r.blurred.v));

  const std::uint8_t* src = o.gaussian_blur ? r.blurred.data() : img.data;
  const std::ptrdiff_t src_stride = o.gaussian_blur ? r.blurred.stride : img.stride;
  Plane<std::int16_t> dx(w, h), dy(w, h);
  Plane<std::uint16_t> mag(w, h);
  k.sobel(src, src_stride, w, h, dx.data(), dy.data(), mag.data(), dx.stride);
  std::int64_t sobel_diff = 0;
  for (std::size_t i = 0; i < dx.v.size(); ++i) {
    sobel_diff += dx.v[i] != r.dx.v[i] || dy.v[i] != r.dy.v[i] || mag.v[i] != r.mag.v[i];
  }
  rep->Line(image, label, "sobel", sobel_diff);

  std::vector<std::uint32_t> hist(kMaxMagnitude + 1);
  CannyTiles th;
  th.Resize(w, h, o);
  k.magnitude_histogram(r.mag.data(), w, h, r.mag.stride, th.shift, hist.data(), th.tile_max.data());
  SelectThresholds(hist.data(), o, &th);
  std::int64_t threshold_diff = (th.frame.low != r.th.frame.low) + (th.frame.high != r.th.frame.high);
  for (std::size_t t = 0; t < th.high.size(); ++t)
    threshold_diff += (th.low[t] != r.th.low[t]) + (th.high[t] != r.th.high[t]);
  rep->Line(image, label, "thresholds", threshold_diff);

  Plane<std::uint8_t> nms(w, h);
  k.nms(r.dx.data(), r.dy.data(), r.mag.data(), w, h, r.dx.stride, r.th.view(), nms.data(), nms.stride);
  rep->Line(image, label, "nms", CountDiff(nms.v, r.nms.v));

  Plane<std::uint8_t> hyst = r.nms;
  std::vector<std::int32_t> stack(static_cast<std::size_t>(w) * h);
  k.hysteresis(hyst.data(), w, h, hyst.stride, stack.data());
  rep->Line(image, label, "hysteresis", CountDiff(hyst.v, r.hyst.v));

  Plane<std::uint8_t> edges(w, h);
  k.edge_sign(r.hyst.data(), r.hyst.stride, r.dx.data(), r.dy.data(), r.dx.stride, w, h, edges.data(),
              edges.stride);
  rep->Line(image, label, "edge_sign", CountDiff(edges.v, r.edges.v));
}

void RunArcStage(const KernelTable& k, const Curves& curves, const Options& o, const ArcStage* inputs,
                 ArcStage* out) {
  std::vector<std::int32_t> stack;
  out->polylines.clear();
  k.polyline(curves, PolylineToleranceQ16(o.polyline_tolerance), &out->polylines, &stack);
  const Polylines& pl = inputs ? inputs->polylines : out->polylines;
  out->splits.clear();
  k.arc_split(curves, pl, SplitTanQ16(o.split_angle_deg), &out->splits);
  const Splits& sp = inputs ? inputs->splits : out->splits;
  out->stats.clear();
  k.arc_stats(curves, sp, o.min_curve_points, &out->stats);
}

void CompareArcs(const KernelTable& k, const Options& o, const Reference& ref, const std::string& image,
                 const std::string& label, Reporter* rep) {
  ArcStage got;
  RunArcStage(k, ref.curves, o, &ref.arcs, &got);
  rep->Line(image, label, "polyline",
            CountDiff(got.polylines.vertex, ref.arcs.polylines.vertex) +
                CountDiff(got.polylines.offset, ref.arcs.polylines.offset));
  rep->Line(image, label, "arc_split",
            CountDiff(got.splits.index, ref.arcs.splits.index) + CountDiff(got.splits.offset, ref.arcs.splits.offset));
  rep->Line(image, label, "arc_stats", CountArcStatsDiff(got.stats, ref.arcs.stats));
}

#ifdef ELLIPSEKIT_HAVE_VULKAN
// The device arc stage on the reference curves. Its three kernels run chained in one submit, so a
// polyline difference would carry into arc_split and arc_stats; false (reported) when it failed.
bool CompareVulkanArcs(VulkanArcStage* stage, const Options& o, const Reference& ref, const std::string& image,
                       Reporter* rep) {
  ArcStage got;
  const Status st = stage->Run(ref.curves, PolylineToleranceQ16(o.polyline_tolerance), SplitTanQ16(o.split_angle_deg),
                               o.min_curve_points, &got.polylines, &got.splits, &got.stats);
  if (!st.ok()) {
    std::fprintf(stderr, "ellipsekit conform: %s: vulkan arc stage failed: %s\n", image.c_str(), st.message().c_str());
    return false;
  }
  rep->Line(image, "vulkan", "polyline",
            CountDiff(got.polylines.vertex, ref.arcs.polylines.vertex) +
                CountDiff(got.polylines.offset, ref.arcs.polylines.offset));
  rep->Line(image, "vulkan", "arc_split",
            CountDiff(got.splits.index, ref.arcs.splits.index) + CountDiff(got.splits.offset, ref.arcs.splits.offset));
  rep->Line(image, "vulkan", "arc_stats", CountArcStatsDiff(got.stats, ref.arcs.stats));
  return true;
}
#endif

// A Detector run compared with the reference's; false (reported) when detection failed.
bool CompareDetector(Detector* detector, const ImageView& img, const Reference& ref, const std::string& image,
                     const std::string& label, Reporter* rep) {
  DetectionResult result;
  const Status st = detector->detect(img, &result);
  if (!st.ok()) {
    std::fprintf(stderr, "ellipsekit conform: %s: %s: detection failed: %s\n", image.c_str(), label.c_str(),
                 st.message().c_str());
    return false;
  }
  rep->Line(image, label, "ellipses", CountEllipseDiff(result.ellipses, ref.result.ellipses));
  return true;
}

// A backend ready to be compared: its CPU table, its Detector, and the Vulkan edge stage.
struct BackendRun {
  Which which;
  std::string label;  // "scalar", "simd", "simd:<target>" or "vulkan", as the report prints it
  const KernelTable* table = nullptr;
  std::unique_ptr<Detector> detector;
#ifdef ELLIPSEKIT_HAVE_VULKAN
  std::unique_ptr<VulkanEdgeStage> vulkan;
  std::unique_ptr<VulkanArcStage> vulkan_arcs;  // null: the device lacks shaderInt64
#endif
};

Backend ToBackend(Which w) {
  switch (w) {
    case Which::kScalar: return Backend::kScalar;
    case Which::kSimd: return Backend::kSimd;
    case Which::kVulkan: return Backend::kVulkan;
  }
  return Backend::kScalar;
}

// Sets up `w` (the SIMD kernels on `simd_target`, "" for the default one); on failure returns
// false with the reason in *why.
bool Prepare(Which w, const Options& base, const std::string& simd_target, BackendRun* c, std::string* why) {
  c->which = w;
  c->label = WhichName(w);
  if (!simd_target.empty()) c->label += ":" + simd_target;
  Options o = base;
  o.backend = ToBackend(w);
  o.simd_target = simd_target;
  std::string fallback;
  const Status st = ResolveKernels(o, &c->table, &fallback);
  if (!st.ok()) {
    *why = st.message();
    return false;
  }
#ifdef ELLIPSEKIT_HAVE_VULKAN
  if (w == Which::kVulkan) {
    const Status vs = VulkanEdgeStage::Create(&c->vulkan);
    if (!vs.ok()) {
      *why = vs.message();
      return false;
    }
    const Status as = VulkanArcStage::Create(&c->vulkan_arcs);
    if (!as.ok())
      std::fprintf(stderr, "ellipsekit conform: %s; comparing the CPU arc kernels the Detector uses instead\n",
                   as.message().c_str());
  }
#endif
  c->detector = std::make_unique<Detector>(o);
  if (!c->detector->status().ok()) {
    *why = c->detector->status().message();
    return false;
  }
  return true;
}

}  // namespace

int RunConform(const std::vector<std::string>& argv) {
  bool help = false;
  const ConformArgs args = ParseConformArgs(argv, &help);
  if (help) {
    std::fputs(kConformUsage, stdout);
    return kExitOk;
  }

  bool failed = false;
  Options options;  // defaults: what the Detector runs
  options.backend = Backend::kScalar;
  Detector reference_detector(options);
  if (!reference_detector.status().ok()) {
    std::fprintf(stderr, "ellipsekit conform: %s\n", reference_detector.status().message().c_str());
    return kExitFailure;
  }

  // One run per backend; with --targets all, one SIMD run per Highway target.
  std::vector<BackendRun> runs;
  for (Which w : args.backends) {
    std::vector<std::string> targets = {""};
#ifdef ELLIPSEKIT_HAVE_SIMD
    if (w == Which::kSimd && args.all_targets) {
      targets.clear();
      for (const simd::TargetKernels& t : simd::Targets()) targets.push_back(t.name);
    }
#endif
    for (const std::string& target : targets) {
      BackendRun c;
      std::string why;
      if (!Prepare(w, options, target, &c, &why)) {
        if (args.backends_given) {
          std::fprintf(stderr, "ellipsekit conform: backend '%s' is unavailable: %s\n", c.label.c_str(), why.c_str());
          failed = true;
        }
        continue;
      }
      runs.push_back(std::move(c));
    }
  }

  Reporter rep;
  for (const std::string& path : args.images) {
    LoadedImage image;
    std::string error;
    if (!LoadImage(path, &image, &error)) {
      std::fprintf(stderr, "ellipsekit conform: %s: %s\n", path.c_str(), error.c_str());
      failed = true;
      continue;
    }
    const ImageView img = ViewOf(image.gray);
    Status st = ValidateImage(img, options);
    if (!st.ok()) {
      std::fprintf(stderr, "ellipsekit conform: %s: %s\n", path.c_str(), st.message().c_str());
      failed = true;
      continue;
    }

    Reference ref;
    RunEdgeChain(ScalarKernels(), img, options, &ref.e);
    {
      TraceScratch trace;
      std::vector<std::int64_t> hull;
      TraceCurves(ref.e.edges.data(), ref.e.edges.stride, ref.e.dx.data(), ref.e.dy.data(), ref.e.dx.stride,
                  img.width, img.height, options.min_curve_points, &ref.curves, &trace);
      FilterCurvesByObb(options, &ref.curves, &hull);
    }
    RunArcStage(ScalarKernels(), ref.curves, options, nullptr, &ref.arcs);
    st = reference_detector.detect(img, &ref.result);
    if (!st.ok()) {
      std::fprintf(stderr, "ellipsekit conform: %s: scalar reference detection failed: %s\n", path.c_str(),
                   st.message().c_str());
      failed = true;
      continue;
    }

    for (BackendRun& c : runs) {
      switch (c.which) {
        case Which::kScalar:
        case Which::kSimd:
          CompareTable(*c.table, img, options, ref, path, c.label, &rep);
          CompareArcs(*c.table, options, ref, path, c.label, &rep);
          failed |= !CompareDetector(c.detector.get(), img, ref, path, c.label, &rep);
          break;
        case Which::kVulkan: {
#ifdef ELLIPSEKIT_HAVE_VULKAN
          const std::size_t n = static_cast<std::size_t>(img.width) * img.height;
          std::vector<std::int16_t> dx(n), dy(n);
          std::vector<std::uint8_t> edges(n);
          const Status vs = c.vulkan->Run(img, options, dx.data(), dy.data(), edges.data());
          if (!vs.ok()) {
            std::fprintf(stderr, "ellipsekit conform: %s: vulkan edge stage failed: %s\n", path.c_str(),
                         vs.message().c_str());
            failed = true;
          } else {
            std::int64_t grad_diff = 0, edge_diff = 0;
            for (int y = 0; y < img.height; ++y) {
              for (int x = 0; x < img.width; ++x) {
                const std::size_t i = static_cast<std::size_t>(y) * img.width + x;
                const std::size_t j = static_cast<std::size_t>(y) * ref.e.dx.stride + x;
                grad_diff += dx[i] != ref.e.dx.v[j] || dy[i] != ref.e.dy.v[j];
                edge_diff += edges[i] != ref.e.edges.v[j];
              }
            }
            rep.Line(path, "vulkan", "sobel", grad_diff);
            rep.Line(path, "vulkan", "edge_sign", edge_diff);
          }
          if (c.vulkan_arcs) {
            failed |= !CompareVulkanArcs(c.vulkan_arcs.get(), options, ref, path, &rep);
          } else {
            CompareArcs(*c.table, options, ref, path, "vulkan", &rep);
          }
#else
          CompareArcs(*c.table, options, ref, path, "vulkan", &rep);
#endif
          failed |= !CompareDetector(c.detector.get(), img, ref, path, "vulkan", &rep);
          break;
        }
      }
    }
    std::fflush(stdout);
  }
  rep.Summary();
  return failed || rep.any_differ() ? kExitFailure : kExitOk;
}

}  // namespace ellipsekit::cli
