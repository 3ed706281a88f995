// detect() allocates nothing after the first frame of a given size (include/ellipsekit/detector.h).
//
// This binary replaces the global operator new / new[] (all variants; the deletes to match) with
// counting versions. Counting is on only while a thread_local flag is set around detect(), so it
// counts the calling thread's allocations; allocations on other threads (a Vulkan driver's worker
// threads, say) are counted separately and reported, not asserted. For the first few counted
// allocations a backtrace is kept, and printed when a case fails, to say where they come from.
#include <execinfo.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "ellipsekit/detector.h"
#include "tools/scenes/crowded_scenes.h"
#include "tools/scenes/scene_generator.h"

namespace {

std::atomic<long> g_counted{0};       // allocations by the counting thread
std::atomic<long> g_counted_bytes{0};
std::atomic<long> g_other{0};         // allocations by any other thread while counting is on
std::atomic<int> g_counting_threads{0};
thread_local bool t_counting = false;
thread_local bool t_in_hook = false;  // backtrace() may allocate: don't recurse

constexpr int kMaxTraces = 4, kTraceDepth = 24;
void* g_traces[kMaxTraces][kTraceDepth];
int g_trace_len[kMaxTraces];
std::size_t g_trace_size[kMaxTraces];
std::atomic<int> g_num_traces{0};

void Record(std::size_t size) {
  if (t_counting) {
    g_counted.fetch_add(1, std::memory_order_relaxed);
    g_counted_bytes.fetch_add(static_cast<long>(size), std::memory_order_relaxed);
    if (!t_in_hook) {
      const int slot = g_num_traces.fetch_add(1);
      if (slot < kMaxTraces) {
        t_in_hook = true;
        g_trace_len[slot] = backtrace(g_traces[slot], kTraceDepth);
        g_trace_size[slot] = size;
        t_in_hook = false;
      }
    }
  } else if (g_counting_threads.load(std::memory_order_relaxed) > 0) {
    g_other.fetch_add(1, std::memory_order_relaxed);
  }
}

void* Allocate(std::size_t size) {
  Record(size);
  if (size == 0) size = 1;
  void* p = std::malloc(size);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}

void* AllocateAligned(std::size_t size, std::align_val_t al) {
  Record(size);
  const std::size_t a = static_cast<std::size_t>(al);
  std::size_t rounded = (size + a - 1) / a * a;
  if (rounded == 0) rounded = a;
  void* p = std::aligned_alloc(a, rounded);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}

}  // namespace

void* operator new(std::size_t n) { return Allocate(n); }
void* operator new[](std::size_t n) { return Allocate(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try { return Allocate(n); } catch (...) { return nullptr; }
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  try { return Allocate(n); } catch (...) { return nullptr; }
}
void* operator new(std::size_t n, std::align_val_t a) { return AllocateAligned(n, a); }
void* operator new[](std::size_t n, std::align_val_t a) { return AllocateAligned(n, a); }
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  try { return AllocateAligned(n, a); } catch (...) { return nullptr; }
}
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  try { return AllocateAligned(n, a); } catch (...) { return nullptr; }
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }

namespace {

using ellipsekit::Backend;

struct Count {
  long allocations = 0, bytes = 0, other_threads = 0;
};

// Runs one detect() with counting on; the allocations it made on this thread (and on others).
Count CountedDetect(ellipsekit::Detector* det, const cv::Mat& m, ellipsekit::DetectionResult* r,
                    ellipsekit::Status* st) {
  ellipsekit::ImageView v;
  v.data = m.data;
  v.width = m.cols;
  v.height = m.rows;
  v.stride = static_cast<std::ptrdiff_t>(m.step[0]);
  g_counted = 0;
  g_counted_bytes = 0;
  g_other = 0;
  g_num_traces = 0;
  g_counting_threads.fetch_add(1);
  t_counting = true;
  *st = det->detect(v, r);
  t_counting = false;
  g_counting_threads.fetch_sub(1);
  return {g_counted.load(), g_counted_bytes.load(), g_other.load()};
}

void PrintTraces() {
  const int n = std::min(g_num_traces.load(), kMaxTraces);
  for (int i = 0; i < n; ++i) {
    std::fprintf(stderr, "  allocation %d (%zu bytes) from:\n", i + 1, g_trace_size[i]);
    backtrace_symbols_fd(g_traces[i], g_trace_len[i], STDERR_FILENO);
  }
}

// Two frames of the same size: scenes 0 and 1 of the seed-7 dataset (640x480), or, failing that,
// two prasad images resized to 640x480.
void Frames(cv::Mat* a, cv::Mat* b) {
  *a = ellipsekit::scenes::RenderScene(ellipsekit::scenes::MixSeed(7, 0)).gray;
  *b = ellipsekit::scenes::RenderScene(ellipsekit::scenes::MixSeed(7, 1)).gray;
}

// Two crowded 1280x720 frames (tools/scenes/crowded_scenes.h): 300 dots and a crate of 150 can
// tops, so the arc-end index, the pair partners, the centre grid of the clustering and (with a
// small triplet budget) the spread order all run at their crowded sizes.
void CrowdedFrames(cv::Mat* a, cv::Mat* b) {
  ellipsekit::scenes::CrowdedSceneOptions o;
  o.width = 1280;
  o.height = 720;
  o.layout = ellipsekit::scenes::CrowdedLayout::kDotGrid;
  o.objects = 300;
  *a = ellipsekit::scenes::RenderCrowdedScene(3, o).gray;
  o.layout = ellipsekit::scenes::CrowdedLayout::kCanCrate;
  o.objects = 150;
  *b = ellipsekit::scenes::RenderCrowdedScene(4, o).gray;
}

void ExpectNoAllocation(Backend backend, void (*frames)(cv::Mat*, cv::Mat*) = Frames, int max_triplets = 0) {
  ellipsekit::Options o;
  o.backend = backend;
  if (max_triplets > 0) o.max_triplets = max_triplets;
  ellipsekit::Detector det(o);
  if (!det.status().ok()) {
    GTEST_SKIP() << ellipsekit::BackendName(backend) << " unavailable: " << det.status().message();
  }
  cv::Mat a, b;
  frames(&a, &b);
  ASSERT_FALSE(a.empty());
  ASSERT_EQ(a.size(), b.size());
  ellipsekit::DetectionResult r;
  ellipsekit::Status st;
  const Count first = CountedDetect(&det, a, &r, &st);
  ASSERT_TRUE(st.ok()) << st.message();
  std::printf("[%s] first frame: %ld allocations (%ld bytes); other threads %ld\n",
              ellipsekit::BackendName(backend), first.allocations, first.bytes, first.other_threads);

  struct Step { const char* what; const cv::Mat* frame; };
  const Step steps[] = {{"same frame again", &a}, {"second frame, same size", &b}, {"second frame again", &b},
                        {"first frame after the second", &a}};
  for (const Step& s : steps) {
    const Count c = CountedDetect(&det, *s.frame, &r, &st);
    ASSERT_TRUE(st.ok()) << st.message();
    std::printf("[%s] %s: %ld allocations (%ld bytes) on the calling thread; other threads %ld; %zu ellipses\n",
                ellipsekit::BackendName(backend), s.what, c.allocations, c.bytes, c.other_threads,
                r.ellipses.size());
    if (c.allocations != 0) {
      std::fprintf(stderr, "ALLOCATION FOUND: backend %s, %s: detect() allocated %ld times (%ld bytes); "
                           "first backtraces:\n",
                   ellipsekit::BackendName(backend), s.what, c.allocations, c.bytes);
      PrintTraces();
    }
    EXPECT_EQ(c.allocations, 0) << "detect() on backend " << ellipsekit::BackendName(backend) << " allocated on '"
                                << s.what << "' (after the first frame of this size); backtraces on stderr";
  }
}

TEST(NoAllocation, Scalar) { ExpectNoAllocation(Backend::kScalar); }
TEST(NoAllocation, Simd) { ExpectNoAllocation(Backend::kSimd); }
TEST(NoAllocation, Vulkan) { ExpectNoAllocation(Backend::kVulkan); }
TEST(NoAllocation, CrowdedFrames) { ExpectNoAllocation(Backend::kSimd, CrowdedFrames); }
TEST(NoAllocation, CrowdedFramesSpentBudget) { ExpectNoAllocation(Backend::kSimd, CrowdedFrames, 200); }

// The counter itself works (guards against a hook that silently is not linked in).
TEST(NoAllocation, CounterSeesAllocations) {
  g_counted = 0;
  t_counting = true;
  auto* p = new std::string(100, 'x');
  t_counting = false;
  delete p;
  EXPECT_GE(g_counted.load(), 1);
  g_num_traces = 0;
}

}  // namespace
