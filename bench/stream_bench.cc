// One iteration submits the 200 scenes to one Stream, keeping `depth` frames in flight, and takes
// every result. items/s is frames per second (detect/<backend>/scenes200 reports the same);
// latency_median_ms and latency_p99_ms are submit-to-result times of the last iteration.
#include "bench/stream_bench.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "bench/bench_frames.h"
#include "bench/end_to_end_bench.h"
#include "ellipsekit/stream.h"

namespace ellipsekit::bench {
namespace {

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
  st.SetItemsProcessed(st.iterations() * static_cast<std::int64_t>(frames.size()));
  std::sort(latency.begin(), latency.end());
  st.counters["latency_median_ms"] = latency[latency.size() / 2];
  st.counters["latency_p99_ms"] = latency[std::min(latency.size() - 1, latency.size() * 99 / 100)];
}

}  // namespace

void RegisterStreamBenchmarks() {
  struct Row { const char* name; Backend backend; };
  for (const Row& b : {Row{"scalar", Backend::kScalar}, Row{"simd", Backend::kSimd}, Row{"vulkan", Backend::kVulkan}}) {
    for (const int depth : {2, 3}) {
      const std::string name = std::string("stream/") + b.name + "/scenes200/depth:" + std::to_string(depth);
      benchmark::RegisterBenchmark(name.c_str(), [backend = b.backend, depth](benchmark::State& st) {
        BM_StreamScenes200(st, backend, depth);
      })->UseRealTime()->Unit(benchmark::kMillisecond);
    }
  }
}

}  // namespace ellipsekit::bench
