// detect() allocates nothing after the first frame of a given size (include/ellipsekit/detector.h).
//
// This binary interposes the C allocator itself (malloc, calloc, realloc, aligned_alloc,
// posix_memalign, memalign; free to match), forwarding to glibc's __libc_* entry points, so every
// allocation counts: operator new (libstdc++'s calls malloc), OpenCV's, the Vulkan loader's and
// driver's. Counting is on only while a thread_local flag is set around detect(): the calling
// thread's allocations are counted; other threads' (a Vulkan driver's worker threads) are counted
// separately and reported, not asserted. Each counted allocation's backtrace says whose it is: one
// made inside the Vulkan loader or driver (a frame in libvulkan*.so, libLLVM*.so or a layer) is
// the driver's own — lavapipe allocates per submit, per fence wait and per JIT-ed dispatch, which
// ellipsekit cannot avoid — and is reported as such; every other one is ellipsekit's and fails.
// For the first few of ours a backtrace is kept and printed when a case fails.
//
// Not under AddressSanitizer (whose runtime owns malloc): there the suite skips.
#include <dlfcn.h>
#include <execinfo.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "ellipsekit/detector.h"
#include "ellipsekit/stream.h"
#include "tools/scenes/crowded_scenes.h"
#include "tools/scenes/scene_generator.h"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define ELLIPSEKIT_COUNT_MALLOC 0
#else
#define ELLIPSEKIT_COUNT_MALLOC 1
#endif

namespace {

std::atomic<long> g_counted{0};       // our allocations on the counting thread
std::atomic<long> g_counted_bytes{0};
std::atomic<long> g_driver{0};        // the Vulkan loader's and driver's, on the counting thread
std::atomic<long> g_other{0};         // allocations by any other thread while counting is on
std::atomic<int> g_counting_threads{0};
thread_local bool t_counting = false;
thread_local bool t_in_hook = false;  // backtrace() and dladdr() may allocate: don't recurse

constexpr int kMaxTraces = 4, kTraceDepth = 32;
void* g_traces[kMaxTraces][kTraceDepth];
int g_trace_len[kMaxTraces];
std::size_t g_trace_size[kMaxTraces];
std::atomic<int> g_num_traces{0};

// Whether a frame of the backtrace lies in the Vulkan loader, a driver or a layer.
bool InsideVulkan(void* const* frames, int n) {
  for (int i = 0; i < n; ++i) {
    Dl_info info;
    if (dladdr(frames[i], &info) == 0 || info.dli_fname == nullptr) continue;
    const char* base = std::strrchr(info.dli_fname, '/');
    base = base ? base + 1 : info.dli_fname;
    if (std::strncmp(base, "libvulkan", 9) == 0 || std::strncmp(base, "libLLVM", 7) == 0 ||
        std::strncmp(base, "libVkLayer", 10) == 0)
      return true;
  }
  return false;
}

void Record(std::size_t size) {
  if (t_in_hook) return;
  if (!t_counting) {
    if (g_counting_threads.load(std::memory_order_relaxed) > 0) g_other.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  t_in_hook = true;
  void* frames[kTraceDepth];
  const int n = backtrace(frames, kTraceDepth);
  if (InsideVulkan(frames, n)) {
    g_driver.fetch_add(1, std::memory_order_relaxed);
  } else {
    g_counted.fetch_add(1, std::memory_order_relaxed);
    g_counted_bytes.fetch_add(static_cast<long>(size), std::memory_order_relaxed);
    const int slot = g_num_traces.fetch_add(1);
    if (slot < kMaxTraces) {
      std::memcpy(g_traces[slot], frames, sizeof(void*) * static_cast<std::size_t>(n));
      g_trace_len[slot] = n;
      g_trace_size[slot] = size;
    }
  }
  t_in_hook = false;
}

}  // namespace

#if ELLIPSEKIT_COUNT_MALLOC
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void __libc_free(void*);

void* malloc(std::size_t n) {
  Record(n);
  return __libc_malloc(n);
}
void* calloc(std::size_t count, std::size_t n) {
  Record(count * n);
  return __libc_calloc(count, n);
}
void* realloc(void* p, std::size_t n) {
  Record(n);
  return __libc_realloc(p, n);
}
void* aligned_alloc(std::size_t alignment, std::size_t n) {
  Record(n);
  return __libc_memalign(alignment, n);
}
void* memalign(std::size_t alignment, std::size_t n) {
  Record(n);
  return __libc_memalign(alignment, n);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t n) {
  Record(n);
  void* p = __libc_memalign(alignment, n);
  if (p == nullptr) return ENOMEM;
  *out = p;
  return 0;
}
void free(void* p) { __libc_free(p); }
}  // extern "C"
#endif

namespace {

using ellipsekit::Backend;

struct Count {
  long allocations = 0, bytes = 0, driver = 0, other_threads = 0;
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
  g_driver = 0;
  g_other = 0;
  g_num_traces = 0;
  g_counting_threads.fetch_add(1);
  t_counting = true;
  *st = det->detect(v, r);
  t_counting = false;
  g_counting_threads.fetch_sub(1);
  return {g_counted.load(), g_counted_bytes.load(), g_driver.load(), g_other.load()};
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

// Two 640x480 frames of fine wavy stripes (periods 4 and 5 px): nearly half their pixels lie on
// long edge curves, beyond the share of a busy frame that a Detector reserves for edge points
// (runtime/detector.cc Resize: 1 in 8). The first grows those buffers, which keep what they grew
// to, so the second, like it, allocates nothing.
void StripeFrames(cv::Mat* a, cv::Mat* b) {
  int period = 4;
  for (cv::Mat* m : {a, b}) {
    m->create(480, 640, CV_8UC1);
    for (int y = 0; y < m->rows; ++y) {
      for (int x = 0; x < m->cols; ++x) {
        const double phase = 2 * CV_PI * (x + 12 * std::sin(y / 25.0)) / period;
        m->at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(128 + 100 * std::sin(phase));
      }
    }
    ++period;
  }
}

void ExpectNoAllocation(Backend backend, void (*frames)(cv::Mat*, cv::Mat*) = Frames, int max_triplets = 0) {
  if (!ELLIPSEKIT_COUNT_MALLOC) GTEST_SKIP() << "the sanitizer's runtime owns malloc; counted in the plain build";
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
  if (frames == StripeFrames) {
    ASSERT_GT(r.num_edge_pixels, a.cols * a.rows / 4) << "the stripes no longer exceed the reserved share";
  }
  std::printf("[%s] first frame: %ld allocations (%ld bytes); Vulkan loader/driver %ld; other threads %ld\n",
              ellipsekit::BackendName(backend), first.allocations, first.bytes, first.driver, first.other_threads);

  struct Step { const char* what; const cv::Mat* frame; };
  const Step steps[] = {{"same frame again", &a}, {"second frame, same size", &b}, {"second frame again", &b},
                        {"first frame after the second", &a}};
  for (const Step& s : steps) {
    const Count c = CountedDetect(&det, *s.frame, &r, &st);
    ASSERT_TRUE(st.ok()) << st.message();
    std::printf("[%s] %s: %ld allocations (%ld bytes) on the calling thread; Vulkan loader/driver %ld "
                "(not ours); other threads %ld; %zu ellipses\n",
                ellipsekit::BackendName(backend), s.what, c.allocations, c.bytes, c.driver, c.other_threads,
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
TEST(NoAllocation, EdgesBeyondTheReservedShare) { ExpectNoAllocation(Backend::kSimd, StripeFrames); }
// A Stream allocates everything when it is created: submit() and wait() on frames of its size
// allocate nothing, neither on the calling thread nor on its worker thread (once the caller's
// StreamResult has taken one result, as a DetectionResult does with detect()).
TEST(NoAllocation, Stream) {
  if (!ELLIPSEKIT_COUNT_MALLOC) GTEST_SKIP() << "the sanitizer's runtime owns malloc; counted in the plain build";
  cv::Mat a, b;
  Frames(&a, &b);
  ellipsekit::Options o;
  o.backend = Backend::kSimd;
  ellipsekit::Stream stream(o, a.cols, a.rows, 2);
  if (!stream.status().ok()) GTEST_SKIP() << stream.status().message();
  ellipsekit::StreamResult r;  // its ellipse vector is sized by the first result it takes
  ASSERT_TRUE(stream.submit({a.data, a.cols, a.rows, static_cast<std::ptrdiff_t>(a.step[0])}, 0).ok());
  ASSERT_TRUE(stream.wait(&r).ok());
  g_counted = 0;
  g_other = 0;
  g_num_traces = 0;
  g_counting_threads.fetch_add(1);
  t_counting = true;
  bool ok = true;
  for (int round = 0; round < 3 && ok; ++round) {
    for (const cv::Mat* m : {&a, &b}) ok = ok && stream.submit({m->data, m->cols, m->rows, static_cast<std::ptrdiff_t>(m->step[0])}, 0).ok();
    for (int i = 0; i < 2 && ok; ++i) ok = stream.wait(&r).ok() && r.status.ok();
  }
  t_counting = false;
  g_counting_threads.fetch_sub(1);
  ASSERT_TRUE(ok);
  if (g_counted.load() != 0) PrintTraces();
  EXPECT_EQ(g_counted.load(), 0) << "submit()/wait() allocated on the calling thread; backtraces on stderr";
  EXPECT_EQ(g_other.load(), 0) << "the stream's worker thread allocated";
}

TEST(NoAllocation, CrowdedFramesSpentBudget) { ExpectNoAllocation(Backend::kSimd, CrowdedFrames, 200); }

// The counter itself works (guards against a hook that silently is not linked in): operator new
// and each C entry point count once.
TEST(NoAllocation, CounterSeesAllocations) {
  if (!ELLIPSEKIT_COUNT_MALLOC) GTEST_SKIP() << "the sanitizer's runtime owns malloc";
  g_counted = 0;
  t_counting = true;
  auto* p = new std::string(100, 'x');
  const long after_new = g_counted.load();
  void* m = std::malloc(64);
  void* c = std::calloc(4, 16);
  m = std::realloc(m, 4096);
  void* a = std::aligned_alloc(64, 128);
  t_counting = false;
  delete p;
  std::free(m);
  std::free(c);
  std::free(a);
  EXPECT_GE(after_new, 1);
  EXPECT_EQ(g_counted.load(), after_new + 4);
  g_num_traces = 0;
}

}  // namespace
