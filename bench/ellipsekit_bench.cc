// ellipsekit_bench: one Google Benchmark registry for the edge-stage kernels, the whole edge stage,
// OpenCV baselines and end-to-end detect(). Run from the repository root (reads
// ../shared/datasets/prasad_subset/images). Every benchmark uses real (wall) time.
//
// Names (scripts/bench.sh parses them):
//   kernel/<kernel>/<backend>/<W>x<H>     kernel: a row of kernels/kernels.inc (stage Edges);
//                                         backend: scalar | simd:<HIGHWAY TARGET>
//   kernel/<kernel>/<backend>/<input>     kernel: a row of kernels/kernels.inc (stage Arcs);
//                                         input: scene (generated scene 0) | prasad (first image);
//                                         items/s = curve points/s
//   edge_stage/<backend>/<W>x<H>          gray in -> sign-classified edge map out; scalar | simd | vulkan
//                                         (| vulkan_steps: with device timestamps per shader step,
//                                         counters <step>_ms and device_ms; | vulkan_cold)
//   arc_stage/<backend>/<input>           curves in -> polylines, splits, arc stats out (the three
//                                         Arcs kernels chained); scalar | vulkan (warm, transfers in)
//                                         | vulkan_timed (with device timestamps: counter device_ms)
//   opencv/<sobel|canny|blur_canny>/<W>x<H>
//   detect/<backend>/<prasad|photos|scenes>/<image>   Detector::detect on the image at its own
//                                         size; photos: the other shared datasets' images,
//                                         named <dataset>_<stem>
//   opencv_blur_canny_image/<prasad|photos|scenes>/<image>   3x3 blur + cv::Canny on the same
//                                         image (BlurCanny, bench_frames.h: detect()'s edge stage
//                                         like for like)
//   detect/<backend>/scenes200, opencv_blur_canny_image/scenes200
//                                         one iteration = all 200 scenes of `ellipsekit scenes
//                                         --count 200 --seed 7` (rendered on first use)
//   detect/crowded/<n>                    four crowded 1280x720 frames of n objects
//                                         (bench/crowded_bench.h); counter ms_per_ellipse
//   memory/<backend>/<W>x<H>              heap a Detector holds after one frame, per pixel
//                                         (bench/memory_bench.h); counter bytes_per_px
//   stream/<backend>/scenes200/depth:<d>  a Stream over the 200 scenes (bench/stream_bench.h);
//                                         items/s = frames/s, latency_median_ms, latency_p99_ms,
//                                         cpu_ms_per_frame; .../detect: the detect() loop beside it
// Test frames for kernels / edge stage: the first prasad image, resized (cv::resize) to each size,
// so the edge density is realistic. OpenCV runs single-threaded (cv::setNumThreads(1)).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "bench/bench_frames.h"
#include "bench/crowded_bench.h"
#include "bench/end_to_end_bench.h"
#include "bench/memory_bench.h"
#include "bench/stream_bench.h"
#include "ellipsekit/detector.h"
#include "kernels/canny_thresholds.h"
#include "kernels/edge_sign.h"
#include "kernels/gaussian.h"
#include "kernels/hysteresis.h"
#include "kernels/nms.h"
#include "kernels/sobel.h"
#include "fit/curve_tracing.h"
#include "kernels/arc_split.h"
#include "kernels/arc_stats.h"
#include "kernels/polyline.h"
#include "runtime/backend.h"
#ifdef ELLIPSEKIT_HAVE_SIMD
#include <hwy/targets.h>  // HWY_TARGETS (the compiled-in targets), hwy::TargetName

#include "cpu/simd_kernels.h"
#endif
#ifdef ELLIPSEKIT_HAVE_VULKAN
#include "runtime/vulkan_arc_stage.h"
#include "runtime/vulkan_edge_stage.h"
#endif
#ifdef ELLIPSEKIT_BENCH_HAVE_SCENES
#include "tools/scenes/scene_generator.h"
#endif

namespace ek = ellipsekit;

namespace {

using namespace ellipsekit::bench;  // bench_frames.h

struct Size {
  int w, h;
};
constexpr Size kSizes[] = {{640, 480}, {1280, 720}, {1920, 1080}};

std::string SizeName(Size s) { return std::to_string(s.w) + "x" + std::to_string(s.h); }

// The base frame: the first dataset image (a synthetic fallback when the dataset is missing).
const cv::Mat& BaseFrame() {
  static const cv::Mat base = [] {
    const auto images = PrasadImages();
    cv::Mat m;
    if (!images.empty()) m = LoadGray(images.front());
    if (m.empty()) {
      std::fprintf(stderr, "ellipsekit_bench: no image in %s; using a synthetic frame\n", kPrasadDir);
      m = cv::Mat(480, 640, CV_8UC1, cv::Scalar(90));
      for (int i = 0; i < 12; ++i)
        cv::ellipse(m, cv::Point(60 + 45 * i, 100 + 25 * i), cv::Size(30 + 3 * i, 15 + 2 * i), 10.0 * i, 0, 360,
                    cv::Scalar(30 + 15 * i), 2);
    }
    return m;
  }();
  return base;
}

Prepared& PreparedFor(Size s) {
  static std::map<std::pair<int, int>, std::unique_ptr<Prepared>> cache;
  auto& slot = cache[{s.w, s.h}];
  if (!slot) {
    slot = std::make_unique<Prepared>();
    cv::Mat resized;
    cv::resize(BaseFrame(), resized, cv::Size(s.w, s.h), 0, 0, cv::INTER_AREA);
    PrepareFrom(resized, slot.get());
  }
  return *slot;
}

// Which CPU kernels a benchmark runs: the scalar references, the SIMD target Backend::kSimd runs
// (ELLIPSEKIT_HWY_TARGET if set, else the best one here), or one Highway target by its HWY_* bit.
constexpr std::int64_t kScalarKernels = 0;
constexpr std::int64_t kDefaultSimdTarget = -1;

#ifdef ELLIPSEKIT_HAVE_SIMD
// nullptr, with the reason in *why, when the CPU lacks `target` (or ELLIPSEKIT_HWY_TARGET names
// no available one).
const ek::simd::TargetKernels* SimdTarget(std::int64_t target, std::string* why) {
  if (target == kDefaultSimdTarget) return ek::simd::FindTarget("", why);
  for (const auto& k : ek::simd::Targets()) {
    if (k.target == target) return &k;
  }
  *why = "Highway target " + std::string(hwy::TargetName(target)) + " not supported by this CPU";
  return nullptr;
}
#endif

// The table for `target`; nullptr, with the benchmark skipped, when SIMD is not built or the CPU
// lacks that target.
const ek::KernelTable* CpuKernels(benchmark::State& st, std::int64_t target) {
  if (target == kScalarKernels) return &ek::ScalarKernels();
#ifdef ELLIPSEKIT_HAVE_SIMD
  std::string why;
  if (const ek::simd::TargetKernels* k = SimdTarget(target, &why)) return &k->table;
  st.SkipWithError(why.c_str());
#else
  st.SkipWithError("SIMD backend not built");
#endif
  return nullptr;
}

// ---- kernels: one function per row of kernels/kernels.inc (stage Edges), from the table of
// `target` (kScalarKernels or a Highway target).
// Bytes: what the kernel reads plus what it writes, per frame.
void RunKernel(benchmark::State& st, const std::string& kernel, std::int64_t target, Size s) {
  Prepared& p = PreparedFor(s);
  const int w = p.w, h = p.h;
  const std::int64_t n = static_cast<std::int64_t>(w) * h;
  const ek::KernelTable* table = CpuKernels(st, target);
  if (table == nullptr) return;
  const ek::KernelTable& t = *table;
  std::vector<std::uint8_t> out_u8(n);
  std::vector<std::int16_t> dx(n), dy(n);
  std::vector<std::uint16_t> mag(n);
  std::vector<std::uint32_t> hist(ek::kMaxMagnitude + 1);
  std::int64_t bytes = 0;
  if (kernel == "gaussian") {
    for (auto _ : st) {
      t.gaussian(p.frame.data, w, w, h, out_u8.data(), w);
      benchmark::DoNotOptimize(out_u8.data());
      benchmark::ClobberMemory();
    }
    bytes = 2 * n;
  } else if (kernel == "sobel") {
    for (auto _ : st) {
      t.sobel(p.blurred.data(), w, w, h, dx.data(), dy.data(), mag.data(), w);
      benchmark::DoNotOptimize(mag.data());
      benchmark::ClobberMemory();
    }
    bytes = 7 * n;
  } else if (kernel == "canny_thresholds") {  // the histogram kernel + the quantile walks + the tiles' pairs
    ek::CannyTiles tiles = p.tiles;
    const ek::Options o;
    for (auto _ : st) {
      t.magnitude_histogram(p.mag.data(), w, h, w, tiles.shift, hist.data(), tiles.tile_max.data());
      ek::SelectThresholds(hist.data(), o, &tiles);
      benchmark::DoNotOptimize(tiles.high.data());
    }
    bytes = 2 * n;
  } else if (kernel == "nms") {
    for (auto _ : st) {
      t.nms(p.dx.data(), p.dy.data(), p.mag.data(), w, h, w, p.tiles.view(), out_u8.data(), w);
      benchmark::DoNotOptimize(out_u8.data());
      benchmark::ClobberMemory();
    }
    bytes = 7 * n;
  } else if (kernel == "hysteresis") {  // in place: each iteration restores the NMS map (memcpy timed)
    for (auto _ : st) {
      std::memcpy(out_u8.data(), p.nms.data(), static_cast<std::size_t>(n));
      t.hysteresis(out_u8.data(), w, h, w, p.stack.data());
      benchmark::DoNotOptimize(out_u8.data());
      benchmark::ClobberMemory();
    }
    bytes = 2 * n;
  } else if (kernel == "edge_sign") {
    for (auto _ : st) {
      t.edge_sign(p.hyst.data(), w, p.dx.data(), p.dy.data(), w, w, h, out_u8.data(), w);
      benchmark::DoNotOptimize(out_u8.data());
      benchmark::ClobberMemory();
    }
    bytes = 6 * n;
  } else {
    st.SkipWithError(("unknown kernel " + kernel).c_str());
    return;
  }
  SetRates(st, n, bytes);
}

// ---- arc-stage kernels: the curves of one frame as the detector traces them (scalar edge stage,
// TraceCurves with T_n; the detector's OBB filter, which needs Eigen, is left out, so a few more
// curves go in), and the scalar reference's polylines and splits as the inputs
// of arc_split and arc_stats. Items are curve points.
struct ArcInputs {
  ek::Curves curves;
  ek::Polylines polylines;
  ek::Splits splits;
  std::vector<ek::ArcStats> stats;
  std::int64_t points = 0;
};

ArcInputs MakeArcInputs(const cv::Mat& frame) {
  Prepared p;
  PrepareFrom(frame, &p);
  const ek::Options o;
  ArcInputs a;
  ek::TraceScratch trace;
  ek::TraceCurves(p.edges.data(), p.w, p.dx.data(), p.dy.data(), p.w, p.w, p.h, o.min_curve_points, &a.curves,
                  &trace);
  std::vector<std::int32_t> stack;
  ek::scalar::Polyline(a.curves, ek::PolylineToleranceQ16(o.polyline_tolerance), &a.polylines, &stack);
  ek::scalar::ArcSplit(a.curves, a.polylines, ek::SplitTanQ16(o.split_angle_deg), &a.splits);
  ek::scalar::ArcStatsFromSplits(a.curves, a.splits, o.min_curve_points, &a.stats);
  a.points = static_cast<std::int64_t>(a.curves.x.size());
  return a;
}

// The frames: "prasad" (the first dataset image, BaseFrame) and "scene" (generated scene 0).
const ArcInputs* ArcInputsFor(const std::string& input) {
  static std::map<std::string, std::unique_ptr<ArcInputs>> cache;
  auto& slot = cache[input];
  if (!slot) {
    cv::Mat frame;
    if (input == "prasad") frame = BaseFrame();
#ifdef ELLIPSEKIT_BENCH_HAVE_SCENES
    if (input == "scene") frame = ek::scenes::RenderScene(ek::scenes::MixSeed(7, 0)).gray;
#endif
    if (frame.empty()) return nullptr;
    slot = std::make_unique<ArcInputs>(MakeArcInputs(frame));
  }
  return slot.get();
}

bool SameArcStats(const std::vector<ek::ArcStats>& a, const std::vector<ek::ArcStats>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const ek::ArcStats &x = a[i], &y = b[i];
    if (x.curve != y.curve || x.begin != y.begin || x.end != y.end || x.x0 != y.x0 || x.y0 != y.y0 || x.x1 != y.x1 ||
        x.y1 != y.y1 || x.xm != y.xm || x.ym != y.ym || x.min_x != y.min_x || x.min_y != y.min_y ||
        x.max_x != y.max_x || x.max_y != y.max_y || x.g0x != y.g0x || x.g0y != y.g0y || x.g1x != y.g1x ||
        x.g1y != y.g1y || x.quadrant != y.quadrant || x.sign_class != y.sign_class) {
      return false;
    }
  }
  return true;
}

// One arc kernel on one frame's curves; outputs are checked against the scalar reference after
// the timed loop. Output buffers are reused across iterations, as in the detector.
void RunArcKernel(benchmark::State& st, const std::string& kernel, std::int64_t target, const std::string& input) {
  const ArcInputs* in = ArcInputsFor(input);
  if (in == nullptr) { st.SkipWithError(("no frame for input " + input).c_str()); return; }
  const ek::KernelTable* table = CpuKernels(st, target);
  if (table == nullptr) return;
  const ek::KernelTable& t = *table;
  const ek::Options o;
  bool same = true;
  if (kernel == "polyline") {
    ek::Polylines out;
    std::vector<std::int32_t> stack;
    const std::int32_t tol = ek::PolylineToleranceQ16(o.polyline_tolerance);
    for (auto _ : st) {
      t.polyline(in->curves, tol, &out, &stack);
      benchmark::DoNotOptimize(out.vertex.data());
    }
    same = out.vertex == in->polylines.vertex && out.offset == in->polylines.offset;
  } else if (kernel == "arc_split") {
    // The Highway version directly: the SIMD table keeps the (faster) reference for arc_split.
    auto* arc_split = t.arc_split;
#ifdef ELLIPSEKIT_HAVE_SIMD
    std::string unused;  // CpuKernels found this target above
    if (target != kScalarKernels) arc_split = SimdTarget(target, &unused)->arc_split;
#endif
    ek::Splits out;
    const std::int64_t tan_q16 = ek::SplitTanQ16(o.split_angle_deg);
    for (auto _ : st) {
      arc_split(in->curves, in->polylines, tan_q16, &out);
      benchmark::DoNotOptimize(out.index.data());
    }
    same = out.index == in->splits.index && out.offset == in->splits.offset;
  } else if (kernel == "arc_stats") {
    std::vector<ek::ArcStats> out;
    for (auto _ : st) {
      out.clear();
      t.arc_stats(in->curves, in->splits, o.min_curve_points, &out);
      benchmark::DoNotOptimize(out.data());
    }
    same = SameArcStats(out, in->stats);
  } else {
    st.SkipWithError(("unknown kernel " + kernel).c_str());
    return;
  }
  if (!same) { st.SkipWithError("output differs from the scalar reference"); return; }
  st.counters["points"] = static_cast<double>(in->points);
  st.counters["curves"] = in->curves.size();
  st.counters["vertices"] = static_cast<double>(in->polylines.vertex.size());
  st.SetItemsProcessed(st.iterations() * in->points);
}

// ---- the whole edge stage, as runtime/detector.cc runs it on a CPU kernel table.
void CpuEdgeStage(const ek::KernelTable& k, const cv::Mat& frame, Prepared* b) {
  const int w = frame.cols, h = frame.rows;
  const ek::Options o;
  k.gaussian(frame.data, static_cast<std::ptrdiff_t>(frame.step[0]), w, h, b->blurred.data(), w);
  k.sobel(b->blurred.data(), w, w, h, b->dx.data(), b->dy.data(), b->mag.data(), w);
  k.magnitude_histogram(b->mag.data(), w, h, w, b->tiles.shift, b->hist.data(), b->tiles.tile_max.data());
  ek::SelectThresholds(b->hist.data(), o, &b->tiles);
  k.nms(b->dx.data(), b->dy.data(), b->mag.data(), w, h, w, b->tiles.view(), b->nms.data(), w);
  k.hysteresis(b->nms.data(), w, h, w, b->stack.data());
  k.edge_sign(b->nms.data(), w, b->dx.data(), b->dy.data(), w, w, h, b->edges.data(), w);
}

void BM_EdgeStageCpu(benchmark::State& st, std::int64_t target, Size s) {
  Prepared& p = PreparedFor(s);
  const ek::KernelTable* table = CpuKernels(st, target);
  if (table == nullptr) return;
  const ek::KernelTable& k = *table;
  Prepared buf;
  PrepareFrom(p.frame, &buf);  // sized buffers (contents overwritten)
  for (auto _ : st) {
    CpuEdgeStage(k, p.frame, &buf);
    benchmark::DoNotOptimize(buf.edges.data());
    benchmark::ClobberMemory();
  }
  if (buf.edges != p.edges) st.SkipWithError("edge map differs from the scalar reference");
  SetRates(st, static_cast<std::int64_t>(p.w) * p.h, 2LL * p.w * p.h);
}

// Turns a shared Vulkan stage's device timestamps (set_timing) on or off for one benchmark, and
// off again after it.
template <class Stage>
class ScopedTiming {
 public:
  ScopedTiming(Stage* stage, bool on) : stage_(stage) { stage_->set_timing(on); }
  ~ScopedTiming() { stage_->set_timing(false); }
  ScopedTiming(const ScopedTiming&) = delete;
  ScopedTiming& operator=(const ScopedTiming&) = delete;

 private:
  Stage* stage_;
};

#ifdef ELLIPSEKIT_HAVE_VULKAN
ek::VulkanEdgeStage* VulkanStage(std::string* why) {
  static std::unique_ptr<ek::VulkanEdgeStage> stage;
  static ek::Status status = [] {
    AtBenchEnd([] { stage.reset(); });
    return ek::VulkanEdgeStage::Create(&stage);
  }();
  if (!status.ok()) *why = status.message();
  return status.ok() ? stage.get() : nullptr;
}
#endif

// Warm (buffers and pipelines made by an untimed first Run); the time includes the transfers.
// steps: with the device timestamps around each shader step (VulkanEdgeStage::set_timing),
// reported as counters device_ms and <step>_ms; they cost time of their own (on lavapipe about a
// dispatch each), so the plain benchmark runs without them.
void BM_EdgeStageVulkan(benchmark::State& st, Size s, bool steps) {
#ifdef ELLIPSEKIT_HAVE_VULKAN
  std::string why;
  ek::VulkanEdgeStage* vk = VulkanStage(&why);
  if (vk == nullptr) { st.SkipWithError(("Vulkan unavailable: " + why).c_str()); return; }
  const ScopedTiming<ek::VulkanEdgeStage> timing(vk, steps);
  Prepared& p = PreparedFor(s);
  const std::size_t n = static_cast<std::size_t>(p.w) * p.h;
  std::vector<std::int16_t> dx(n), dy(n);
  std::vector<std::uint8_t> edges(n);
  const ek::Options o;
  ek::Status rs = vk->Run(View(p.frame), o, dx.data(), dy.data(), edges.data());
  if (!rs.ok()) { st.SkipWithError(("Vulkan Run failed: " + rs.message()).c_str()); return; }
  using Stage = ek::VulkanEdgeStage;
  double device_ms = 0, step_ms[Stage::kNumSteps] = {};
  for (auto _ : st) {
    rs = vk->Run(View(p.frame), o, dx.data(), dy.data(), edges.data());
    if (!rs.ok()) { st.SkipWithError(("Vulkan Run failed: " + rs.message()).c_str()); break; }
    device_ms += vk->last_device_ms();
    for (int s = 0; s < Stage::kNumSteps; ++s) step_ms[s] += vk->last_step_device_ms(static_cast<Stage::Step>(s));
  }
  if (st.error_occurred()) return;
  if (edges != p.edges) { st.SkipWithError("edge map differs from the scalar reference"); return; }
  if (steps) {
    st.counters["device_ms"] = benchmark::Counter(device_ms, benchmark::Counter::kAvgIterations);
    // Device time per shader step (timestamps), e.g. "nms_ms".
    for (int s = 0; s < Stage::kNumSteps; ++s) {
      st.counters[std::string(Stage::StepName(static_cast<Stage::Step>(s))) + "_ms"] =
          benchmark::Counter(step_ms[s], benchmark::Counter::kAvgIterations);
    }
  }
  st.SetLabel(vk->device_name());
  SetRates(st, static_cast<std::int64_t>(n), 2LL * static_cast<std::int64_t>(n));
#else
  (void)s;
  (void)steps;
  st.SkipWithError("Vulkan backend not built");
#endif
}

// Cold: each iteration creates the stage (instance, device, pipelines through a new pipeline
// cache, buffers) and runs its first frame: what a program pays once, at start-up.
void BM_EdgeStageVulkanCold(benchmark::State& st, Size s) {
#ifdef ELLIPSEKIT_HAVE_VULKAN
  Prepared& p = PreparedFor(s);
  const std::size_t n = static_cast<std::size_t>(p.w) * p.h;
  std::vector<std::int16_t> dx(n), dy(n);
  std::vector<std::uint8_t> edges(n);
  const ek::Options o;
  for (auto _ : st) {
    std::unique_ptr<ek::VulkanEdgeStage> vk;
    ek::Status rs = ek::VulkanEdgeStage::Create(&vk);
    if (rs.ok()) rs = vk->Run(View(p.frame), o, dx.data(), dy.data(), edges.data());
    if (!rs.ok()) { st.SkipWithError(rs.message().c_str()); break; }
  }
  if (st.error_occurred()) return;
  if (edges != p.edges) { st.SkipWithError("edge map differs from the scalar reference"); return; }
  SetRates(st, static_cast<std::int64_t>(n), 2LL * static_cast<std::int64_t>(n));
#else
  (void)s;
  st.SkipWithError("Vulkan backend not built");
#endif
}

// ---- the whole arc stage on one frame's curves (ArcInputsFor): polyline -> arc_split -> arc_stats,
// each fed the one before, as fit/arc_selection.cc runs them. scalar: the reference kernels;
// vulkan: runtime/vulkan_arc_stage.h, warm (an untimed first Run sizes its buffers), upload and
// download included; timed: with the device timestamps (VulkanArcStage::set_timing), counter
// device_ms. Outputs are checked against the scalar reference after the timed loop.
void BM_ArcStage(benchmark::State& st, bool vulkan, bool timed, const std::string& input) {
  const ArcInputs* in = ArcInputsFor(input);
  if (in == nullptr) { st.SkipWithError(("no frame for input " + input).c_str()); return; }
  const ek::Options o;
  const std::int32_t tol = ek::PolylineToleranceQ16(o.polyline_tolerance);
  const std::int64_t tan_q16 = ek::SplitTanQ16(o.split_angle_deg);
  ek::Polylines polylines;
  ek::Splits splits;
  std::vector<ek::ArcStats> stats;
  if (!vulkan) {
    std::vector<std::int32_t> stack;
    for (auto _ : st) {
      ek::scalar::Polyline(in->curves, tol, &polylines, &stack);
      ek::scalar::ArcSplit(in->curves, polylines, tan_q16, &splits);
      stats.clear();
      ek::scalar::ArcStatsFromSplits(in->curves, splits, o.min_curve_points, &stats);
      benchmark::DoNotOptimize(stats.data());
    }
  } else {
#ifdef ELLIPSEKIT_HAVE_VULKAN
    static std::unique_ptr<ek::VulkanArcStage> stage;
    static const ek::Status created = [] {
      AtBenchEnd([] { stage.reset(); });
      return ek::VulkanArcStage::Create(&stage);
    }();
    if (!created.ok()) { st.SkipWithError(created.message().c_str()); return; }
    const ScopedTiming<ek::VulkanArcStage> timing(stage.get(), timed);
    ek::Status rs = stage->Run(in->curves, tol, tan_q16, o.min_curve_points, &polylines, &splits, &stats);
    if (!rs.ok()) { st.SkipWithError(("Vulkan arc stage failed: " + rs.message()).c_str()); return; }
    double device_ms = 0, compact_ms = 0;
    for (auto _ : st) {
      stats.clear();
      rs = stage->Run(in->curves, tol, tan_q16, o.min_curve_points, &polylines, &splits, &stats);
      if (!rs.ok()) { st.SkipWithError(("Vulkan arc stage failed: " + rs.message()).c_str()); break; }
      device_ms += stage->last_device_ms();
      compact_ms += stage->last_compact_ms();
    }
    if (st.error_occurred()) return;
    if (timed) st.counters["device_ms"] = benchmark::Counter(device_ms, benchmark::Counter::kAvgIterations);
    st.counters["compact_ms"] = benchmark::Counter(compact_ms, benchmark::Counter::kAvgIterations);
    st.counters["rounds"] = stage->last_rounds();
    st.SetLabel(stage->device_name());
#else
    st.SkipWithError("Vulkan backend not built");
    return;
#endif
  }
  if (polylines.vertex != in->polylines.vertex || polylines.offset != in->polylines.offset ||
      splits.index != in->splits.index || splits.offset != in->splits.offset || !SameArcStats(stats, in->stats)) {
    st.SkipWithError("arc stage output differs from the scalar reference");
    return;
  }
  st.counters["points"] = static_cast<double>(in->points);
  st.counters["curves"] = in->curves.size();
  st.SetItemsProcessed(st.iterations() * in->points);
}

// ---- OpenCV baselines (single thread). Canny uses the thresholds our rule picks for the frame, with
// OpenCV's default L1 gradient (as ours); blur_canny adds the 3x3 Gaussian ours applies.
void BM_OpenCvSobel(benchmark::State& st, Size s) {
  Prepared& p = PreparedFor(s);
  cv::Mat dx, dy;
  for (auto _ : st) {
    cv::Sobel(p.frame, dx, CV_16S, 1, 0, 3);
    cv::Sobel(p.frame, dy, CV_16S, 0, 1, 3);
    benchmark::DoNotOptimize(dx.data);
    benchmark::DoNotOptimize(dy.data);
  }
  SetRates(st, static_cast<std::int64_t>(p.w) * p.h, 5LL * p.w * p.h);
}

void BM_OpenCvCanny(benchmark::State& st, bool blur, Size s) {
  Prepared& p = PreparedFor(s);
  cv::Mat blurred, edges;
  for (auto _ : st) {
    if (blur) {
      BlurCanny(p.frame, p.th, &blurred, &edges);
    } else {
      cv::Canny(p.frame, edges, p.th.low, p.th.high, 3, false);
    }
    benchmark::DoNotOptimize(edges.data);
  }
  SetRates(st, static_cast<std::int64_t>(p.w) * p.h, 2LL * p.w * p.h);
}

// Registers kernel/<kernel>/scalar<tail> and the SIMD variants: kernel/<kernel>/simd:<target><tail>
// per Highway target in `targets` (each skips itself where the CPU lacks it), or
// kernel/<kernel>/simd<tail> (which skips itself) when SIMD is not built. run(st, target) runs
// the kernel.
void RegisterKernel(const std::string& kernel, const std::string& tail, const std::vector<std::int64_t>& targets,
                    const std::function<void(benchmark::State&, std::int64_t)>& run) {
  const std::string name = "kernel/" + kernel;
  benchmark::RegisterBenchmark((name + "/scalar" + tail).c_str(),
                               [run](benchmark::State& st) { run(st, kScalarKernels); })->UseRealTime();
#ifdef ELLIPSEKIT_HAVE_SIMD
  for (std::int64_t t : targets) {
    benchmark::RegisterBenchmark((name + "/simd:" + hwy::TargetName(t) + tail).c_str(),
                                 [run, t](benchmark::State& st) { run(st, t); })
        ->UseRealTime();
  }
#else
  (void)targets;
  benchmark::RegisterBenchmark((name + "/simd" + tail).c_str(),
                               [run](benchmark::State& st) { run(st, kDefaultSimdTarget); })->UseRealTime();
#endif
}

void Register() {
  const char* kernels[] = {
#define ELLIPSEKIT_KERNEL(name, stage) ELLIPSEKIT_KERNEL_##stage(name)
#define ELLIPSEKIT_KERNEL_Edges(name) #name,
#define ELLIPSEKIT_KERNEL_Arcs(name)
#include "kernels/kernels.inc"
#undef ELLIPSEKIT_KERNEL_Edges
#undef ELLIPSEKIT_KERNEL_Arcs
  };

  std::vector<std::int64_t> targets;  // every Highway target compiled into this binary, best first
#ifdef ELLIPSEKIT_HAVE_SIMD
  for (int i = 0; i < 63; ++i) {
    const std::uint64_t bit = std::uint64_t{1} << i;
    if (static_cast<std::uint64_t>(HWY_TARGETS) & bit) targets.push_back(static_cast<std::int64_t>(bit));
  }
#endif

  for (const char* k : kernels) {
    for (Size s : kSizes) {
      std::string tail = "/";  // (appends: GCC 12 warns falsely on "literal" + string)
      tail += SizeName(s);
      RegisterKernel(k, tail, targets, [k, s](benchmark::State& st, std::int64_t t) { RunKernel(st, k, t, s); });
    }
  }

  const char* arc_kernels[] = {
#define ELLIPSEKIT_KERNEL(name, stage) ELLIPSEKIT_KERNEL_##stage(name)
#define ELLIPSEKIT_KERNEL_Edges(name)
#define ELLIPSEKIT_KERNEL_Arcs(name) #name,
#include "kernels/kernels.inc"
#undef ELLIPSEKIT_KERNEL_Edges
#undef ELLIPSEKIT_KERNEL_Arcs
  };
  for (const char* k : arc_kernels) {
    for (const char* input : {"scene", "prasad"}) {
      const std::string in(input);
      RegisterKernel(k, "/" + in, targets,
                     [k, in](benchmark::State& st, std::int64_t t) { RunArcKernel(st, k, t, in); });
    }
  }

  for (const char* input : {"scene", "prasad"}) {
    const std::string in(input);
    benchmark::RegisterBenchmark(("arc_stage/scalar/" + in).c_str(),
                                 [in](benchmark::State& st) { BM_ArcStage(st, false, false, in); })->UseRealTime();
    benchmark::RegisterBenchmark(("arc_stage/vulkan/" + in).c_str(),
                                 [in](benchmark::State& st) { BM_ArcStage(st, true, false, in); })->UseRealTime();
    benchmark::RegisterBenchmark(("arc_stage/vulkan_timed/" + in).c_str(),
                                 [in](benchmark::State& st) { BM_ArcStage(st, true, true, in); })->UseRealTime();
  }

  for (Size s : kSizes) {
    std::string tail = "/";  // (appends: see above)
    tail += SizeName(s);
    benchmark::RegisterBenchmark(("edge_stage/scalar" + tail).c_str(),
                                 [s](benchmark::State& st) { BM_EdgeStageCpu(st, kScalarKernels, s); })->UseRealTime();
    benchmark::RegisterBenchmark(("edge_stage/simd" + tail).c_str(),
                                 [s](benchmark::State& st) { BM_EdgeStageCpu(st, kDefaultSimdTarget, s); })->UseRealTime();
    benchmark::RegisterBenchmark(("edge_stage/vulkan" + tail).c_str(),
                                 [s](benchmark::State& st) { BM_EdgeStageVulkan(st, s, false); })->UseRealTime();
    benchmark::RegisterBenchmark(("edge_stage/vulkan_steps" + tail).c_str(),
                                 [s](benchmark::State& st) { BM_EdgeStageVulkan(st, s, true); })->UseRealTime();
    benchmark::RegisterBenchmark(("edge_stage/vulkan_cold" + tail).c_str(),
                                 [s](benchmark::State& st) { BM_EdgeStageVulkanCold(st, s); })->UseRealTime();
    benchmark::RegisterBenchmark(("opencv/sobel" + tail).c_str(),
                                 [s](benchmark::State& st) { BM_OpenCvSobel(st, s); })->UseRealTime();
    benchmark::RegisterBenchmark(("opencv/canny" + tail).c_str(),
                                 [s](benchmark::State& st) { BM_OpenCvCanny(st, false, s); })->UseRealTime();
    benchmark::RegisterBenchmark(("opencv/blur_canny" + tail).c_str(),
                                 [s](benchmark::State& st) { BM_OpenCvCanny(st, true, s); })->UseRealTime();
  }

  // A 64x48 frame: almost no pixels, so what is left is each backend's fixed cost per frame (on
  // Vulkan: the dispatches and barriers, the submit and the fence wait).
  static constexpr Size kTiny{64, 48};
  benchmark::RegisterBenchmark(("edge_stage/simd/" + SizeName(kTiny)).c_str(),
                               [](benchmark::State& st) { BM_EdgeStageCpu(st, kDefaultSimdTarget, kTiny); })->UseRealTime();
  benchmark::RegisterBenchmark(("edge_stage/vulkan/" + SizeName(kTiny)).c_str(),
                               [](benchmark::State& st) { BM_EdgeStageVulkan(st, kTiny, false); })->UseRealTime();
  benchmark::RegisterBenchmark(("edge_stage/vulkan_steps/" + SizeName(kTiny)).c_str(),
                               [](benchmark::State& st) { BM_EdgeStageVulkan(st, kTiny, true); })->UseRealTime();

}

}  // namespace

int main(int argc, char** argv) {
  cv::setNumThreads(1);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  Register();
  ellipsekit::bench::RegisterEndToEndBenchmarks();
  ellipsekit::bench::RegisterCrowdedBenchmarks();
  ellipsekit::bench::RegisterMemoryBenchmarks();
  ellipsekit::bench::RegisterStreamBenchmarks();
  benchmark::RunSpecifiedBenchmarks();
  ReleaseBenchResources();
  benchmark::Shutdown();
  return 0;
}
