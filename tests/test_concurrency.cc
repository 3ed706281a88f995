// Concurrency and determinism: 8 threads, each with its own Detector, over the same 50 generated
// frames give results identical (bit for bit) to one thread, and repeated runs are identical too.
// Also run under ThreadSanitizer by `scripts/test.sh --tsan`.
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "ellipsekit/ellipsekit.h"
#include "tools/scenes/scene_generator.h"
#include "tests/ellipse_test_util.h"

namespace ellipsekit {
namespace {

constexpr int kFrames = 50;
constexpr int kThreads = 8;

// Everything of a result except the timings, which legitimately differ.
struct Outcome {
  StatusCode code = StatusCode::kOk;
  std::vector<Ellipse> ellipses;
  Backend backend = Backend::kScalar;
  unsigned caps_hit = 0;
  int num_edge_pixels = 0, num_curves = 0, num_arcs = 0, num_candidates = 0;
};

::testing::AssertionResult Same(const Outcome& a, const Outcome& b) {
  if (a.code != b.code || a.backend != b.backend || a.caps_hit != b.caps_hit ||
      a.num_edge_pixels != b.num_edge_pixels || a.num_curves != b.num_curves || a.num_arcs != b.num_arcs ||
      a.num_candidates != b.num_candidates)
    return ::testing::AssertionFailure() << "counts differ: ellipses " << a.ellipses.size() << " vs "
                                         << b.ellipses.size() << ", arcs " << a.num_arcs << " vs " << b.num_arcs
                                         << ", candidates " << a.num_candidates << " vs " << b.num_candidates;
  return test::SameEllipses(a.ellipses, b.ellipses);
}

const std::vector<scenes::Scene>& Frames() {
  static const std::vector<scenes::Scene> frames = [] {
    std::vector<scenes::Scene> v;
    for (int i = 0; i < kFrames; ++i) v.push_back(scenes::RenderScene(scenes::MixSeed(2024, i)));
    return v;
  }();
  return frames;
}

std::vector<Outcome> RunAll(const Options& options) {
  Detector det(options);
  std::vector<Outcome> out(kFrames);
  DetectionResult r;
  for (int i = 0; i < kFrames; ++i) {
    const cv::Mat& g = Frames()[i].gray;
    const Status st = det.detect({g.ptr<std::uint8_t>(), g.cols, g.rows, static_cast<std::ptrdiff_t>(g.step[0])}, &r);
    Outcome& o = out[i];
    o.code = st.code();
    o.ellipses = r.ellipses;
    o.backend = r.backend;
    o.caps_hit = r.caps_hit;
    o.num_edge_pixels = r.num_edge_pixels;
    o.num_curves = r.num_curves;
    o.num_arcs = r.num_arcs;
    o.num_candidates = r.num_candidates;
  }
  return out;
}

class Concurrency : public ::testing::TestWithParam<Backend> {};

TEST_P(Concurrency, EightThreadsMatchOneThreadAndRepeatedRuns) {
  Options options;
  options.backend = GetParam();
  {
    Detector probe(options);
    if (probe.status().code() == StatusCode::kUnavailable) GTEST_SKIP() << probe.status().message();
    ASSERT_TRUE(probe.status().ok()) << probe.status().message();
  }
  Frames();  // rendered once, before any thread starts
  const std::vector<Outcome> reference = RunAll(options);
  int with_ellipses = 0;
  for (const Outcome& o : reference) {
    ASSERT_EQ(o.code, StatusCode::kOk);
    with_ellipses += !o.ellipses.empty();
  }
  EXPECT_GT(with_ellipses, kFrames / 2) << "the frames should mostly contain detections";

  // Repeated single-thread run: identical.
  const std::vector<Outcome> again = RunAll(options);
  for (int i = 0; i < kFrames; ++i) EXPECT_TRUE(Same(reference[i], again[i])) << "repeat, frame " << i;

  // 8 threads at once, each with its own Detector, each over all frames (in a shifted order so that
  // different threads work on different frames at the same moment).
  std::vector<std::vector<Outcome>> per_thread(kThreads, std::vector<Outcome>(kFrames));
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      Detector det(options);
      DetectionResult r;
      for (int k = 0; k < kFrames; ++k) {
        const int i = (k + t * 7) % kFrames;
        const cv::Mat& g = Frames()[i].gray;
        const Status st =
            det.detect({g.ptr<std::uint8_t>(), g.cols, g.rows, static_cast<std::ptrdiff_t>(g.step[0])}, &r);
        Outcome& o = per_thread[t][i];
        o.code = st.code();
        o.ellipses = r.ellipses;
        o.backend = r.backend;
        o.caps_hit = r.caps_hit;
        o.num_edge_pixels = r.num_edge_pixels;
        o.num_curves = r.num_curves;
        o.num_arcs = r.num_arcs;
        o.num_candidates = r.num_candidates;
      }
    });
  }
  for (std::thread& th : threads) th.join();
  for (int t = 0; t < kThreads; ++t)
    for (int i = 0; i < kFrames; ++i) EXPECT_TRUE(Same(reference[i], per_thread[t][i])) << "thread " << t << ", frame " << i;
}

INSTANTIATE_TEST_SUITE_P(Backends, Concurrency, ::testing::Values(Backend::kScalar, Backend::kAuto),
                         [](const auto& info) { return std::string(BackendName(info.param)); });

}  // namespace
}  // namespace ellipsekit
