// detect() allocates nothing after the first frame of a given size (include/ellipsekit/detector.h).
//
// Allocations are counted by tests/alloc_counter.h (the C allocator interposed, each allocation
// attributed by its backtrace: the Vulkan loader's and driver's own -- lavapipe allocates per
// submit, per fence wait and per JIT-ed dispatch -- are reported, not asserted; every other one
// on the calling thread is ellipsekit's and fails). Not under AddressSanitizer: there the suite
// skips.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "ellipsekit/detector.h"
#include "ellipsekit/stream.h"
#include "tests/alloc_counter.h"
#include "tools/eval/sensor_noise.h"
#include "tools/scenes/crowded_scenes.h"
#include "tools/scenes/scene_generator.h"

namespace {

using ellipsekit::Backend;

using ellipsekit::test::AllocationCount;
using ellipsekit::test::CountAllocations;
using ellipsekit::test::PrintAllocationTraces;

// Runs one detect() with counting on; the allocations it made on this thread (and on others).
AllocationCount CountedDetect(ellipsekit::Detector* det, const cv::Mat& m, ellipsekit::DetectionResult* r,
                              ellipsekit::Status* st) {
  ellipsekit::ImageView v;
  v.data = m.data;
  v.width = m.cols;
  v.height = m.rows;
  v.stride = static_cast<std::ptrdiff_t>(m.step[0]);
  return CountAllocations([&] { *st = det->detect(v, r); });
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

// Scenes 0 and 1 with sensor noise of standard deviation 7 and 11 added: one and two extra
// smoothing passes before the edges (Options::denoise_min_sigma).
void NoisyFrames(cv::Mat* a, cv::Mat* b) {
  Frames(a, b);
  ellipsekit::eval::AddSensorNoise(7, 1, a);
  ellipsekit::eval::AddSensorNoise(11, 2, b);
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
  if (!ellipsekit::test::kCountsAllocations) GTEST_SKIP() << "the sanitizer's runtime owns malloc; counted in the plain build";
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
  const AllocationCount first = CountedDetect(&det, a, &r, &st);
  ASSERT_TRUE(st.ok()) << st.message();
  if (frames == NoisyFrames) {
    ellipsekit::DetectionResult second;
    ellipsekit::Status st2;
    CountedDetect(&det, b, &second, &st2);
    ASSERT_TRUE(st2.ok()) << st2.message();
    ASSERT_EQ(r.denoise_passes, 1) << r.noise_sigma;
    ASSERT_EQ(second.denoise_passes, 2) << second.noise_sigma;
  }
  if (frames == StripeFrames) {
    ASSERT_GT(r.num_edge_pixels, a.cols * a.rows / 4) << "the stripes no longer exceed the reserved share";
  }
  std::printf("[%s] first frame: %ld allocations (%ld bytes); Vulkan loader/driver %ld; other threads %ld\n",
              ellipsekit::BackendName(backend), first.allocations, first.bytes, first.driver, first.other_threads);

  struct Step { const char* what; const cv::Mat* frame; };
  const Step steps[] = {{"same frame again", &a}, {"second frame, same size", &b}, {"second frame again", &b},
                        {"first frame after the second", &a}};
  for (const Step& s : steps) {
    const AllocationCount c = CountedDetect(&det, *s.frame, &r, &st);
    ASSERT_TRUE(st.ok()) << st.message();
    std::printf("[%s] %s: %ld allocations (%ld bytes) on the calling thread; Vulkan loader/driver %ld "
                "(not ours); other threads %ld; %zu ellipses\n",
                ellipsekit::BackendName(backend), s.what, c.allocations, c.bytes, c.driver, c.other_threads,
                r.ellipses.size());
    if (c.allocations != 0) {
      std::fprintf(stderr, "ALLOCATION FOUND: backend %s, %s: detect() allocated %ld times (%ld bytes); "
                           "first backtraces:\n",
                   ellipsekit::BackendName(backend), s.what, c.allocations, c.bytes);
      PrintAllocationTraces();
    }
    EXPECT_EQ(c.allocations, 0) << "detect() on backend " << ellipsekit::BackendName(backend) << " allocated on '"
                                << s.what << "' (after the first frame of this size); backtraces on stderr";
  }
}

TEST(NoAllocation, Scalar) { ExpectNoAllocation(Backend::kScalar); }
TEST(NoAllocation, Simd) { ExpectNoAllocation(Backend::kSimd); }
TEST(NoAllocation, Vulkan) { ExpectNoAllocation(Backend::kVulkan); }
TEST(NoAllocation, CrowdedFrames) { ExpectNoAllocation(Backend::kSimd, CrowdedFrames); }
TEST(NoAllocation, NoisyFrames) { ExpectNoAllocation(Backend::kSimd, NoisyFrames); }
TEST(NoAllocation, EdgesBeyondTheReservedShare) { ExpectNoAllocation(Backend::kSimd, StripeFrames); }
// A Stream allocates everything when it is created: submit() and wait() on frames of its size
// allocate nothing, neither on the calling thread nor on its worker thread (once the caller's
// StreamResult has taken one result, as a DetectionResult does with detect()).
TEST(NoAllocation, Stream) {
  if (!ellipsekit::test::kCountsAllocations) GTEST_SKIP() << "the sanitizer's runtime owns malloc; counted in the plain build";
  cv::Mat a, b;
  Frames(&a, &b);
  ellipsekit::Options o;
  o.backend = Backend::kSimd;
  ellipsekit::Stream stream(o, a.cols, a.rows, 2);
  if (!stream.status().ok()) GTEST_SKIP() << stream.status().message();
  ellipsekit::StreamResult r;  // its ellipse vector is sized by the first result it takes
  ASSERT_TRUE(stream.submit({a.data, a.cols, a.rows, static_cast<std::ptrdiff_t>(a.step[0])}, 0).ok());
  ASSERT_TRUE(stream.wait(&r).ok());
  bool ok = true;
  const AllocationCount c = CountAllocations([&] {
    for (int round = 0; round < 3 && ok; ++round) {
      for (const cv::Mat* m : {&a, &b}) ok = ok && stream.submit({m->data, m->cols, m->rows, static_cast<std::ptrdiff_t>(m->step[0])}, 0).ok();
      for (int i = 0; i < 2 && ok; ++i) ok = stream.wait(&r).ok() && r.status.ok();
    }
  });
  ASSERT_TRUE(ok);
  if (c.allocations != 0) PrintAllocationTraces();
  EXPECT_EQ(c.allocations, 0) << "submit()/wait() allocated on the calling thread; backtraces on stderr";
  EXPECT_EQ(c.other_threads, 0) << "the stream's worker thread allocated";
}

TEST(NoAllocation, CrowdedFramesSpentBudget) { ExpectNoAllocation(Backend::kSimd, CrowdedFrames, 200); }

// The counter itself works (guards against a hook that silently is not linked in): operator new
// and each C entry point count once.
TEST(NoAllocation, CounterSeesAllocations) {
  if (!ellipsekit::test::kCountsAllocations) GTEST_SKIP() << "the sanitizer's runtime owns malloc";
  std::string* p = nullptr;
  const AllocationCount just_new = CountAllocations([&] { p = new std::string(100, 'x'); });
  delete p;
  void *m = nullptr, *c = nullptr, *a = nullptr;
  const AllocationCount all = CountAllocations([&] {
    p = new std::string(100, 'x');
    m = std::malloc(64);
    c = std::calloc(4, 16);
    m = std::realloc(m, 4096);
    a = std::aligned_alloc(64, 128);
  });
  delete p;
  std::free(m);
  std::free(c);
  std::free(a);
  EXPECT_GE(just_new.allocations, 1);
  EXPECT_EQ(all.allocations, just_new.allocations + 4);
}

}  // namespace
