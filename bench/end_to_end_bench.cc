#include "bench/end_to_end_bench.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "bench/bench_frames.h"
#include "ellipsekit/detector.h"
#include "runtime/backend.h"
#ifdef ELLIPSEKIT_BENCH_HAVE_SCENES
#include "tools/scenes/scene_generator.h"
#endif

namespace ellipsekit::bench {

namespace ek = ellipsekit;

namespace {

constexpr int kNumScenes = 6;  // generated scenes benchmarked one by one (scene_0000 ...)

// ---- end to end. One Detector per backend, reused across images (a warm-up detect() per
// benchmark sizes its buffers). Stage timings are averaged over the iterations as counters.
ek::Detector* DetectorFor(ek::Backend b) {
  static std::map<int, std::unique_ptr<ek::Detector>> detectors;
  static const bool registered = [] {
    AtBenchEnd([] { detectors.clear(); });
    return true;
  }();
  (void)registered;
  auto& d = detectors[static_cast<int>(b)];
  if (!d) {
    ek::Options o;
    o.backend = b;
    d = std::make_unique<ek::Detector>(o);
  }
  return d.get();
}

// The shared Detector of `backend` on the best Highway target, or nullptr after skipping the
// benchmark when the backend is unavailable here.
ek::Detector* ReadyDetector(benchmark::State& st, ek::Backend backend) {
  ek::Detector* det = DetectorFor(backend);
  if (!det->status().ok()) {
    st.SkipWithError((std::string(ek::BackendName(backend)) + " unavailable: " + det->status().message()).c_str());
    return nullptr;
  }
  return det;
}

void BM_Detect(benchmark::State& st, ek::Backend backend, const cv::Mat* image) {
  ek::Detector* det = ReadyDetector(st, backend);
  if (det == nullptr) return;
  ek::DetectionResult r;
  ek::Status s = det->detect(View(*image), &r);
  if (!s.ok()) { st.SkipWithError(("detect failed: " + s.message()).c_str()); return; }
  ek::StageTimings sum;
  for (auto _ : st) {
    s = det->detect(View(*image), &r);
    sum.edges_ms += r.timings.edges_ms;
    sum.curves_ms += r.timings.curves_ms;
    sum.arcs_ms += r.timings.arcs_ms;
    sum.fit_ms += r.timings.fit_ms;
    sum.validate_ms += r.timings.validate_ms;
    sum.total_ms += r.timings.total_ms;
  }
  if (!s.ok()) { st.SkipWithError(("detect failed: " + s.message()).c_str()); return; }
  using C = benchmark::Counter;
  st.counters["edges_ms"] = C(sum.edges_ms, C::kAvgIterations);
  st.counters["curves_ms"] = C(sum.curves_ms, C::kAvgIterations);
  st.counters["arcs_ms"] = C(sum.arcs_ms, C::kAvgIterations);
  st.counters["fit_ms"] = C(sum.fit_ms, C::kAvgIterations);
  st.counters["validate_ms"] = C(sum.validate_ms, C::kAvgIterations);
  st.counters["total_ms"] = C(sum.total_ms, C::kAvgIterations);
  st.counters["ellipses"] = static_cast<double>(r.ellipses.size());
  st.counters["edge_pixels"] = r.num_edge_pixels;
  SetRates(st, static_cast<std::int64_t>(image->cols) * image->rows,
           static_cast<std::int64_t>(image->cols) * image->rows);
}

void BM_BlurCannyImage(benchmark::State& st, const Prepared* p) {
  cv::Mat blurred, edges;
  for (auto _ : st) {
    BlurCanny(p->frame, p->th, &blurred, &edges);
    benchmark::DoNotOptimize(edges.data);
  }
  SetRates(st, static_cast<std::int64_t>(p->w) * p->h, 2LL * p->w * p->h);
}

#ifdef ELLIPSEKIT_BENCH_HAVE_SCENES
// The 200 generated scenes and the Canny thresholds the edge stage picks on each (for the
// baseline), made once, on first use, so runs that filter them out do not pay for them.
struct SceneSet {
  std::vector<cv::Mat> frames;
  std::vector<ek::CannyThresholds> th;
};
const SceneSet& Scenes200() {
  static const SceneSet set = [] {
    SceneSet s;
    Prepared p;
    for (int i = 0; i < 200; ++i) {
      s.frames.push_back(ek::scenes::RenderScene(ek::scenes::MixSeed(7, static_cast<std::uint64_t>(i))).gray);
      PrepareFrom(s.frames.back(), &p);
      s.th.push_back(p.th);
    }
    return s;
  }();
  return set;
}

void BM_DetectScenes200(benchmark::State& st, ek::Backend backend) {
  // frames/s as items/s, beside stream/<backend>/scenes200 (stream_bench.h)
  ek::Detector* det = ReadyDetector(st, backend);
  if (det == nullptr) return;
  const SceneSet& set = Scenes200();
  ek::DetectionResult r;
  for (auto _ : st) {
    for (const cv::Mat& f : set.frames) {
      if (!det->detect(View(f), &r).ok()) { st.SkipWithError("detect failed"); return; }
    }
  }
  st.SetItemsProcessed(st.iterations() * static_cast<std::int64_t>(set.frames.size()));
}

void BM_BlurCannyScenes200(benchmark::State& st) {
  const SceneSet& set = Scenes200();
  cv::Mat blurred, edges;
  for (auto _ : st) {
    for (std::size_t i = 0; i < set.frames.size(); ++i) {
      BlurCanny(set.frames[i], set.th[i], &blurred, &edges);
      benchmark::DoNotOptimize(edges.data);
    }
  }
}
#endif

std::vector<std::pair<std::string, cv::Mat>>& EndToEndImages(const std::string& set) {
  static std::map<std::string, std::vector<std::pair<std::string, cv::Mat>>> sets;
  return sets[set];
}

}  // namespace

void RegisterEndToEndBenchmarks() {
  // Every prasad image, the other shared photographs, and kNumScenes generated scenes.
  auto& prasad = EndToEndImages("prasad");
  for (const auto& path : PrasadImages()) {
    cv::Mat m = LoadGray(path);
    if (!m.empty()) prasad.emplace_back(path.stem().string(), m);
  }
  // The other shared photographs (every dataset but prasad_subset), named <dataset>_<stem>.
  auto& photos = EndToEndImages("photos");
  std::error_code ec;
  std::vector<std::filesystem::path> datasets;
  for (const auto& e : std::filesystem::directory_iterator(kSharedDatasetsDir, ec))
    if (e.is_directory() && e.path().filename() != "prasad_subset") datasets.push_back(e.path());
  std::sort(datasets.begin(), datasets.end());
  for (const auto& d : datasets) {
    for (const auto& path : ImagesIn(d / "images")) {
      cv::Mat m = LoadGray(path);
      if (!m.empty()) photos.emplace_back(d.filename().string() + "_" + path.stem().string(), m);
    }
  }
  auto& scenes = EndToEndImages("scenes");
#ifdef ELLIPSEKIT_BENCH_HAVE_SCENES
  for (int i = 0; i < kNumScenes; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "scene_%04d", i);
    scenes.emplace_back(name, ek::scenes::RenderScene(ek::scenes::MixSeed(7, static_cast<std::uint64_t>(i))).gray);
  }
#endif
  static std::vector<std::unique_ptr<Prepared>> prepared;  // thresholds for the Canny baselines
  const std::pair<ek::Backend, const char*> backends[] = {
      {ek::Backend::kScalar, "scalar"}, {ek::Backend::kSimd, "simd"}, {ek::Backend::kVulkan, "vulkan"}};
  for (const char* set : {"prasad", "photos", "scenes"}) {
    for (auto& [name, mat] : EndToEndImages(set)) {
      if (!mat.isContinuous()) mat = mat.clone();
      const cv::Mat* img = &mat;
      for (const auto& [b, bname] : backends) {
        const ek::Backend backend = b;
        benchmark::RegisterBenchmark(("detect/" + std::string(bname) + "/" + set + "/" + name).c_str(),
                                     [backend, img](benchmark::State& st) { BM_Detect(st, backend, img); })
            ->UseRealTime();
      }
      prepared.push_back(std::make_unique<Prepared>());
      PrepareFrom(mat, prepared.back().get());
      const Prepared* p = prepared.back().get();
      benchmark::RegisterBenchmark(("opencv_blur_canny_image/" + std::string(set) + "/" + name).c_str(),
                                   [p](benchmark::State& st) { BM_BlurCannyImage(st, p); })->UseRealTime();
    }
  }
#ifdef ELLIPSEKIT_BENCH_HAVE_SCENES
  for (const auto& [b, bname] : backends) {
    const ek::Backend backend = b;
    benchmark::RegisterBenchmark(("detect/" + std::string(bname) + "/scenes200").c_str(),
                                 [backend](benchmark::State& st) { BM_DetectScenes200(st, backend); })
        ->UseRealTime();
  }
  benchmark::RegisterBenchmark("opencv_blur_canny_image/scenes200", BM_BlurCannyScenes200)->UseRealTime();
#endif
}

const std::vector<cv::Mat>& GeneratedScenes200() {
#ifdef ELLIPSEKIT_BENCH_HAVE_SCENES
  return Scenes200().frames;
#else
  static const std::vector<cv::Mat> kNone;
  return kNone;
#endif
}

}  // namespace ellipsekit::bench
