// One iteration submits the 200 scenes to one Stream, keeping `depth` frames in flight, and takes
// every result; the detect rows run Detector::detect() over the same frames one after another, the
// baseline a stream is measured against (detect/<backend>/scenes200 times the same loop, without
// these counters). items/s is frames per second. Counters: latency_median_ms and latency_p99_ms,
// submit-to-result times (detect: the call's time) of the last iteration; cpu_ms_per_frame, the
// process's CPU time over all iterations per frame (every thread: the stream's worker, and on
// lavapipe the driver's threads, which run the shaders on this machine's cores).
#include "bench/stream_bench.h"

#include <benchmark/benchmark.h>

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "bench/bench_frames.h"
#include "bench/end_to_end_bench.h"
#include "ellipsekit/detector.h"
#include "ellipsekit/stream.h"

namespace ellipsekit::bench {
namespace {

double ProcessCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

void SetCounters(benchmark::State& st, std::size_t frames, double cpu_ms, std::vector<double>* latency) {
  st.SetItemsProcessed(st.iterations() * static_cast<std::int64_t>(frames));
  std::sort(latency->begin(), latency->end());
  st.counters["latency_median_ms"] = (*latency)[latency->size() / 2];
  st.counters["latency_p99_ms"] = (*latency)[std::min(latency->size() - 1, latency->size() * 99 / 100)];
  st.counters["cpu_ms_per_frame"] = cpu_ms / (static_cast<double>(st.iterations()) * static_cast<double>(frames));
}

void BM_StreamScenes200(benchmark::State& st, Backend backend, int depth) {
  const std::vector<cv::Mat>& frames = GeneratedScenes200();
  if (frames.empty()) {
    st.SkipWithError("no generated scenes in this build");
    return;
  }
  Options o;
  o.backend = backend;
  Stream stream(o, frames[0].cols, frames[0].rows, depth);
  if (!stream.status().ok()) {
    st.SkipWithError(stream.status().message().c_str());
    return;
  }
  std::vector<double> latency;
  latency.reserve(frames.size());
  StreamResult r;
  auto take = [&] {
    if (!stream.wait(&r).ok() || !r.status.ok()) return false;
    latency.push_back(r.latency_ms);
    return true;
  };
  const double cpu0 = ProcessCpuMs();
  for (auto _ : st) {
    latency.clear();
    for (std::size_t i = 0; i < frames.size(); ++i) {
      if (stream.in_flight() == depth && !take()) {
        st.SkipWithError("stream frame failed");
        return;
      }
      if (!stream.submit(View(frames[i]), i).ok()) {
        st.SkipWithError("submit failed");
        return;
      }
    }
    while (stream.in_flight() > 0) {
      if (!take()) {
        st.SkipWithError("stream frame failed");
        return;
      }
    }
  }
  SetCounters(st, frames.size(), ProcessCpuMs() - cpu0, &latency);
}

// The baseline: one Detector (made here and warmed on the first frame), detect() frame by frame.
void BM_DetectLoopScenes200(benchmark::State& st, Backend backend) {
  const std::vector<cv::Mat>& frames = GeneratedScenes200();
  if (frames.empty()) {
    st.SkipWithError("no generated scenes in this build");
    return;
  }
  Options o;
  o.backend = backend;
  Detector det(o);
  DetectionResult r;
  if (!det.status().ok() || !det.detect(View(frames[0]), &r).ok()) {
    st.SkipWithError(("detect failed: " + det.status().message()).c_str());
    return;
  }
  std::vector<double> latency;
  latency.reserve(frames.size());
  using Clock = std::chrono::steady_clock;
  const double cpu0 = ProcessCpuMs();
  for (auto _ : st) {
    latency.clear();
    for (const cv::Mat& f : frames) {
      const Clock::time_point t0 = Clock::now();
      if (!det.detect(View(f), &r).ok()) {
        st.SkipWithError("detect failed");
        return;
      }
      latency.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    }
  }
  SetCounters(st, frames.size(), ProcessCpuMs() - cpu0, &latency);
}

}  // namespace

void RegisterStreamBenchmarks() {
  struct Row { const char* name; Backend backend; };
  for (const Row& b : {Row{"scalar", Backend::kScalar}, Row{"simd", Backend::kSimd}, Row{"vulkan", Backend::kVulkan}}) {
    const std::string prefix = std::string("stream/") + b.name + "/scenes200/";
    benchmark::RegisterBenchmark((prefix + "detect").c_str(), [backend = b.backend](benchmark::State& st) {
      BM_DetectLoopScenes200(st, backend);
    })->UseRealTime()->Unit(benchmark::kMillisecond);
    for (const int depth : {2, 3}) {
      benchmark::RegisterBenchmark((prefix + "depth:" + std::to_string(depth)).c_str(),
                                   [backend = b.backend, depth](benchmark::State& st) {
                                     BM_StreamScenes200(st, backend, depth);
                                   })->UseRealTime()->Unit(benchmark::kMillisecond);
    }
  }
}

}  // namespace ellipsekit::bench
