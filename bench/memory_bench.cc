// One iteration creates a Detector, runs it on one frame (the first prasad image, resized with
// cv::resize to the size, so the edge density is a photograph's) and destroys it. Counters, read
// while the Detector is alive after its frame:
//   bytes_per_px     heap bytes in use (glibc mallinfo2: arena + mmapped blocks) minus those in
//                    use before the Detector was created, over width * height. Everything the
//                    Detector reserved, touched or not; for Vulkan, also what the driver allocated
//                    with malloc (its device memory is not on this heap).
//   address_per_px   the growth of the process's address space (VmSize in /proc/self/status)
//                    over the same interval, over width * height: what RLIMIT_AS sees. glibc keeps
//                    freed pages mapped, so this is an upper bound that depends on what ran before.
//   caps_bytes       the part of bytes_per_px that does not scale with the frame: the same
//                    measurement on a 64x48 frame, in bytes.
#include "bench/memory_bench.h"

#include <benchmark/benchmark.h>
#include <malloc.h>

#include <cstdio>
#include <cstring>
#include <string>

#include <opencv2/imgproc.hpp>

#include "bench/bench_frames.h"
#include "ellipsekit/detector.h"

namespace ellipsekit::bench {
namespace {

long HeapInUse() {
  const struct mallinfo2 m = mallinfo2();
  return static_cast<long>(m.uordblks + m.hblkhd);
}

long AddressSpace() {  // bytes; 0 when /proc is not readable
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (f == nullptr) return 0;
  char line[256];
  long kb = 0;
  while (std::fgets(line, sizeof line, f) != nullptr) {
    if (std::strncmp(line, "VmSize:", 7) == 0) kb = std::atol(line + 7);
  }
  std::fclose(f);
  return kb * 1024;
}

struct Held {
  long heap = 0, address = 0;
};

// What a Detector of `backend` holds after one frame; false (and *why) when it cannot run.
bool Measure(Backend backend, const cv::Mat& frame, Held* held, std::string* why) {
  Options o;
  o.backend = backend;
  const long heap0 = HeapInUse(), address0 = AddressSpace();
  Detector det(o);
  if (!det.status().ok()) {
    *why = det.status().message();
    return false;
  }
  DetectionResult r;
  const Status st = det.detect(View(frame), &r);
  if (!st.ok()) {
    *why = st.message();
    return false;
  }
  held->heap = HeapInUse() - heap0;
  held->address = AddressSpace() - address0;
  return true;
}

void RunMemory(benchmark::State& st, Backend backend, int w, int h) {
  const std::vector<std::filesystem::path> images = PrasadImages();
  if (images.empty()) {
    st.SkipWithError("no prasad images");
    return;
  }
  cv::Mat frame, tiny;
  cv::resize(LoadGray(images.front()), frame, cv::Size(w, h), 0, 0, cv::INTER_AREA);
  cv::resize(frame, tiny, cv::Size(64, 48), 0, 0, cv::INTER_AREA);
  Held held, caps;
  std::string why;
  for (auto _ : st) {
    if (!Measure(backend, frame, &held, &why) || !Measure(backend, tiny, &caps, &why)) {
      st.SkipWithError(why.c_str());
      return;
    }
  }
  const double pixels = static_cast<double>(w) * h;
  st.counters["bytes_per_px"] = static_cast<double>(held.heap) / pixels;
  st.counters["address_per_px"] = static_cast<double>(held.address) / pixels;
  st.counters["caps_bytes"] = static_cast<double>(caps.heap);
}

}  // namespace

void RegisterMemoryBenchmarks() {
  struct Row { const char* name; Backend backend; };
  for (const Row& b : {Row{"scalar", Backend::kScalar}, Row{"simd", Backend::kSimd}, Row{"vulkan", Backend::kVulkan}}) {
    for (const auto& [w, h] : {std::pair{640, 480}, std::pair{1920, 1080}}) {
      const std::string name = std::string("memory/") + b.name + "/" + std::to_string(w) + "x" + std::to_string(h);
      benchmark::RegisterBenchmark(name.c_str(), [backend = b.backend, w = w, h = h](benchmark::State& st) {
        RunMemory(st, backend, w, h);
      })->Iterations(1)->Unit(benchmark::kMillisecond);
    }
  }
}

}  // namespace ellipsekit::bench
