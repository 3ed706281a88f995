// What a Detector reserves (issue "Figures a reviewer can trust": at most 32 bytes per pixel plus
// what its caps need, in address space, not only in touched pages).
//
// UnderAddressSpaceLimit: detect() on a 640x480 and a 1920x1080 frame in a child process whose
// address space (RLIMIT_AS) is its size at the fork + 64 MB and + 160 MB, on every CPU backend
// (Vulkan's driver maps its own memory). The old sizing (~613 bytes per pixel: 188 MB at 640x480,
// 1.27 GB at 1920x1080) failed both with std::bad_alloc.
// HeapPerPixel: the heap a Detector holds after its first frame (glibc mallinfo2), at 1920x1080
// minus at 64x48 (what does not scale with the frame: the caps' buffers), per pixel, <= 32.
// Not under a sanitizer: its shadow memory and allocator make both figures meaningless.
#include <malloc.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "ellipsekit/detector.h"
#include "tools/scenes/crowded_scenes.h"
#include "tools/scenes/scene_generator.h"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define ELLIPSEKIT_UNDER_SANITIZER 1
#else
#define ELLIPSEKIT_UNDER_SANITIZER 0
#endif

namespace {

using ellipsekit::Backend;

long AddressSpaceBytes() {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (f == nullptr) return -1;
  char line[256];
  long kb = -1;
  while (std::fgets(line, sizeof line, f) != nullptr) {
    if (std::strncmp(line, "VmSize:", 7) == 0) kb = std::atol(line + 7);
  }
  std::fclose(f);
  return kb < 0 ? -1 : kb * 1024;
}

ellipsekit::ImageView View(const cv::Mat& m) {
  return {m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step[0])};
}

// A 640x480 generated tabletop scene, or a crowded 1920x1080 crate of 200 can tops (dense edges).
cv::Mat Frame(int width) {
  if (width == 640) return ellipsekit::scenes::RenderScene(ellipsekit::scenes::MixSeed(7, 3)).gray;
  ellipsekit::scenes::CrowdedSceneOptions o;
  o.width = 1920;
  o.height = 1080;
  o.layout = ellipsekit::scenes::CrowdedLayout::kCanCrate;
  o.objects = 200;
  return ellipsekit::scenes::RenderCrowdedScene(5, o).gray;
}

// Exit status of a child that limits its address space to its size + `budget` bytes, creates a
// Detector of `backend` and detects on `frame` twice: 0 ok, 3 unavailable backend, else failure
// (1 Detector status, 2 detect status, 4 no /proc, 5 setrlimit).
int DetectUnderLimit(Backend backend, const cv::Mat& frame, long budget) {
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    const long base = AddressSpaceBytes();
    if (base < 0) _exit(4);
    const rlimit limit{static_cast<rlim_t>(base + budget), static_cast<rlim_t>(base + budget)};
    if (setrlimit(RLIMIT_AS, &limit) != 0) _exit(5);
    ellipsekit::Options o;
    o.backend = backend;
    ellipsekit::Detector det(o);
    if (det.status().code() == ellipsekit::StatusCode::kUnavailable) _exit(3);
    if (!det.status().ok()) _exit(1);
    ellipsekit::DetectionResult r;
    for (int i = 0; i < 2; ++i) {
      const ellipsekit::Status st = det.detect(View(frame), &r);
      if (!st.ok()) {
        std::fprintf(stderr, "detect under the limit: %s\n", st.message().c_str());
        _exit(2);
      }
    }
    _exit(0);
  }
  int status = 0;
  if (pid < 0 || waitpid(pid, &status, 0) != pid) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

TEST(MemoryLimit, UnderAddressSpaceLimit) {
  if (ELLIPSEKIT_UNDER_SANITIZER) GTEST_SKIP() << "a sanitizer reserves terabytes of shadow address space";
  constexpr long kMB = 1L << 20;
  struct Case { int width; long budget; };
  for (const Case c : {Case{640, 64 * kMB}, Case{1920, 160 * kMB}}) {
    const cv::Mat frame = Frame(c.width);
    ASSERT_FALSE(frame.empty());
    for (const Backend b : {Backend::kScalar, Backend::kSimd, Backend::kAuto}) {
      const int rc = DetectUnderLimit(b, frame, c.budget);
      if (rc == 3) continue;  // a build without SIMD
      EXPECT_EQ(rc, 0) << ellipsekit::BackendName(b) << " at " << frame.cols << "x" << frame.rows << " under +"
                       << c.budget / kMB << " MB of address space (1 Detector status, 2 detect status)";
    }
  }
}

long HeapInUse() {
  const struct mallinfo2 m = mallinfo2();
  return static_cast<long>(m.uordblks + m.hblkhd);
}

// Heap bytes a Detector of `backend` holds after one frame.
long HeapHeld(Backend backend, const cv::Mat& frame) {
  const long before = HeapInUse();
  ellipsekit::Options o;
  o.backend = backend;
  ellipsekit::Detector det(o);
  EXPECT_TRUE(det.status().ok()) << det.status().message();
  ellipsekit::DetectionResult r;
  EXPECT_TRUE(det.detect(View(frame), &r).ok());
  return HeapInUse() - before;
}

TEST(MemoryLimit, HeapPerPixel) {
  if (ELLIPSEKIT_UNDER_SANITIZER) GTEST_SKIP() << "the sanitizer's allocator does not report to mallinfo2";
  const cv::Mat large = Frame(1920);
  cv::Mat tiny;
  cv::resize(large, tiny, cv::Size(64, 48), 0, 0, cv::INTER_AREA);
  for (const Backend b : {Backend::kScalar, Backend::kAuto}) {
    const long caps = HeapHeld(b, tiny), held = HeapHeld(b, large);
    const double per_pixel = static_cast<double>(held - caps) / (1920.0 * 1080 - 64 * 48);
    std::printf("[%s] heap held: %.1f MB at 1920x1080, %.2f MB at 64x48 (caps): %.1f bytes per pixel\n",
                ellipsekit::BackendName(b), held / 1e6, caps / 1e6, per_pixel);
    EXPECT_LE(per_pixel, 32.0) << ellipsekit::BackendName(b);
  }
}

}  // namespace
