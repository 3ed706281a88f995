// Counts heap allocations for the no-allocation tests (the hot-path contract, DESIGN.md). Include
// it in exactly one translation unit of a test binary (each tests/*.cc is its own binary): it
// interposes the C allocator (malloc, calloc, realloc, aligned_alloc, posix_memalign, memalign;
// free to match), forwarding to glibc's __libc_* entry points, so every allocation counts:
// operator new (libstdc++'s calls malloc), OpenCV's, the Vulkan loader's and driver's.
//
// CountAllocations(f) counts while f runs: the calling thread's allocations, each attributed by
// its backtrace -- one made inside the Vulkan loader, a driver or a layer (a frame in
// libvulkan*.so, libLLVM*.so, libVkLayer*.so) is the driver's own, which ellipsekit cannot avoid
// (lavapipe allocates per submit, fence wait and JIT-ed dispatch); every other one is ours -- and,
// separately, other threads' (a stream's worker, a driver's threads). The first few of ours keep a
// backtrace for PrintAllocationTraces().
//
// Not under AddressSanitizer or ThreadSanitizer, whose runtimes own malloc: kCountsAllocations is
// false there and the tests skip.
#pragma once

#include <dlfcn.h>
#include <execinfo.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstddef>
#include <cstdio>
#include <cstring>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define ELLIPSEKIT_COUNT_MALLOC 0
#else
#define ELLIPSEKIT_COUNT_MALLOC 1
#endif

namespace ellipsekit::test {

inline constexpr bool kCountsAllocations = ELLIPSEKIT_COUNT_MALLOC;

struct AllocationCount {
  long allocations = 0;   // ours, on the calling thread
  long bytes = 0;         // their sizes
  long driver = 0;        // the Vulkan loader's, driver's or a layer's, on the calling thread
  long other_threads = 0; // by any other thread meanwhile
};

namespace alloc_detail {

inline std::atomic<long> counted{0}, counted_bytes{0}, driver{0}, other{0};
inline std::atomic<int> counting_threads{0};
inline thread_local bool counting = false;
inline thread_local bool in_hook = false;  // backtrace() and dladdr() may allocate: don't recurse

inline constexpr int kMaxTraces = 4, kTraceDepth = 32;
inline void* traces[kMaxTraces][kTraceDepth];
inline int trace_len[kMaxTraces];
inline std::size_t trace_size[kMaxTraces];
inline std::atomic<int> num_traces{0};

inline bool InsideVulkan(void* const* frames, int n) {
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

inline void Record(std::size_t size) {
  if (in_hook) return;
  if (!counting) {
    if (counting_threads.load(std::memory_order_relaxed) > 0) other.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  in_hook = true;
  void* frames[kTraceDepth];
  const int n = backtrace(frames, kTraceDepth);
  if (InsideVulkan(frames, n)) {
    driver.fetch_add(1, std::memory_order_relaxed);
  } else {
    counted.fetch_add(1, std::memory_order_relaxed);
    counted_bytes.fetch_add(static_cast<long>(size), std::memory_order_relaxed);
    const int slot = num_traces.fetch_add(1);
    if (slot < kMaxTraces) {
      std::memcpy(traces[slot], frames, sizeof(void*) * static_cast<std::size_t>(n));
      trace_len[slot] = n;
      trace_size[slot] = size;
    }
  }
  in_hook = false;
}

}  // namespace alloc_detail

// Runs f() with counting on; what it (and other threads meanwhile) allocated.
template <class F>
AllocationCount CountAllocations(F&& f) {
  namespace d = alloc_detail;
  d::counted = 0;
  d::counted_bytes = 0;
  d::driver = 0;
  d::other = 0;
  d::num_traces = 0;
  d::counting_threads.fetch_add(1);
  d::counting = true;
  f();
  d::counting = false;
  d::counting_threads.fetch_sub(1);
  return {d::counted.load(), d::counted_bytes.load(), d::driver.load(), d::other.load()};
}

// The backtraces of the first (up to 4) of our allocations in the last CountAllocations, on stderr.
inline void PrintAllocationTraces() {
  namespace d = alloc_detail;
  const int n = std::min(d::num_traces.load(), d::kMaxTraces);
  for (int i = 0; i < n; ++i) {
    std::fprintf(stderr, "  allocation %d (%zu bytes) from:\n", i + 1, d::trace_size[i]);
    backtrace_symbols_fd(d::traces[i], d::trace_len[i], STDERR_FILENO);
  }
}

}  // namespace ellipsekit::test

#if ELLIPSEKIT_COUNT_MALLOC
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void __libc_free(void*);

void* malloc(std::size_t n) {
  ellipsekit::test::alloc_detail::Record(n);
  return __libc_malloc(n);
}
void* calloc(std::size_t count, std::size_t n) {
  ellipsekit::test::alloc_detail::Record(count * n);
  return __libc_calloc(count, n);
}
void* realloc(void* p, std::size_t n) {
  ellipsekit::test::alloc_detail::Record(n);
  return __libc_realloc(p, n);
}
void* aligned_alloc(std::size_t alignment, std::size_t n) {
  ellipsekit::test::alloc_detail::Record(n);
  return __libc_memalign(alignment, n);
}
void* memalign(std::size_t alignment, std::size_t n) {
  ellipsekit::test::alloc_detail::Record(n);
  return __libc_memalign(alignment, n);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t n) {
  ellipsekit::test::alloc_detail::Record(n);
  void* p = __libc_memalign(alignment, n);
  if (p == nullptr) return ENOMEM;
  *out = p;
  return 0;
}
void free(void* p) { __libc_free(p); }
}  // extern "C"
#endif
