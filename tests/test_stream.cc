// Stream (include/ellipsekit/stream.h): results in submission order, each the ellipses detect()
// gives on the same frame, on every backend, with 1-3 frames in flight and with frames polled
// or waited for; and the errors of a wrong frame, a full stream and an empty one.
#include <cstdint>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "ellipsekit/stream.h"
#include "tools/scenes/scene_generator.h"
#include "tests/ellipse_test_util.h"

namespace {

using ellipsekit::Backend;

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr int kScenes = 24;  // the sanitizers slow every frame ~10x
#else
constexpr int kScenes = 200;  // the set: `ellipsekit scenes --count 200 --seed 7`
#endif

const std::vector<cv::Mat>& Scenes() {
  static const std::vector<cv::Mat> frames = [] {
    std::vector<cv::Mat> f;
    for (int i = 0; i < kScenes; ++i)
      f.push_back(ellipsekit::scenes::RenderScene(ellipsekit::scenes::MixSeed(7, static_cast<std::uint64_t>(i))).gray);
    return f;
  }();
  return frames;
}

ellipsekit::ImageView View(const cv::Mat& m) {
  return {m.data, m.cols, m.rows, static_cast<std::ptrdiff_t>(m.step[0])};
}

void ExpectSame(const ellipsekit::DetectionResult& want, const ellipsekit::StreamResult& got, int frame) {
  ASSERT_TRUE(got.status.ok()) << "frame " << frame << ": " << got.status.message();
  ASSERT_EQ(got.tag, static_cast<std::uint64_t>(frame));
  const ellipsekit::DetectionResult& r = got.result;
  EXPECT_TRUE(ellipsekit::test::SameEllipses(r.ellipses, want.ellipses)) << "frame " << frame;
  EXPECT_EQ(r.num_edge_pixels, want.num_edge_pixels);
  EXPECT_EQ(r.num_arcs, want.num_arcs);
  EXPECT_EQ(r.num_candidates, want.num_candidates);
  EXPECT_EQ(r.backend, want.backend);
  EXPECT_GT(got.latency_ms, 0);
}

// Keeps `depth` frames in flight (waiting, or polling until a result is ready), then drains.
void ExpectStreamEqualsDetect(Backend backend, int depth, bool use_poll) {
  ellipsekit::Options o;
  o.backend = backend;
  ellipsekit::Detector det(o);
  if (det.status().code() == ellipsekit::StatusCode::kUnavailable) GTEST_SKIP() << det.status().message();
  const std::vector<cv::Mat>& frames = Scenes();
  ellipsekit::Stream stream(o, frames[0].cols, frames[0].rows, depth);
  ASSERT_TRUE(stream.status().ok()) << stream.status().message();
  ellipsekit::DetectionResult want;
  ellipsekit::StreamResult got;
  int next_result = 0;
  auto take = [&] {
    if (use_poll) {
      while (!stream.poll(&got)) std::this_thread::yield();
    } else {
      ASSERT_TRUE(stream.wait(&got).ok());
    }
    ASSERT_TRUE(det.detect(View(frames[static_cast<std::size_t>(next_result)]), &want).ok());
    ExpectSame(want, got, next_result);
    ++next_result;
  };
  for (int i = 0; i < static_cast<int>(frames.size()); ++i) {
    if (stream.in_flight() == depth) take();
    ASSERT_TRUE(stream.submit(View(frames[static_cast<std::size_t>(i)]), static_cast<std::uint64_t>(i)).ok());
  }
  while (stream.in_flight() > 0) take();
  EXPECT_EQ(next_result, static_cast<int>(frames.size()));
}

TEST(Stream, ScalarDepth2) { ExpectStreamEqualsDetect(Backend::kScalar, 2, false); }
TEST(Stream, SimdDepth2) { ExpectStreamEqualsDetect(Backend::kSimd, 2, false); }
TEST(Stream, SimdDepth3Polled) { ExpectStreamEqualsDetect(Backend::kSimd, 3, true); }
TEST(Stream, SimdDepth1) { ExpectStreamEqualsDetect(Backend::kSimd, 1, false); }
TEST(Stream, VulkanDepth2) { ExpectStreamEqualsDetect(Backend::kVulkan, 2, false); }

TEST(Stream, Errors) {
  const cv::Mat& frame = Scenes()[0];
  ellipsekit::Options o;
  EXPECT_FALSE(ellipsekit::Stream(o, 640, 480, 0).status().ok());
  EXPECT_FALSE(ellipsekit::Stream(o, 640, 480, ellipsekit::Stream::kMaxDepth + 1).status().ok());
  EXPECT_FALSE(ellipsekit::Stream(o, 0, 480, 2).status().ok());
  ellipsekit::Options bad;
  bad.min_curve_points = 1;
  EXPECT_FALSE(ellipsekit::Stream(bad, 640, 480, 2).status().ok());

  ellipsekit::Stream stream(o, frame.cols, frame.rows, 2);
  ASSERT_TRUE(stream.status().ok());
  ellipsekit::StreamResult r;
  EXPECT_FALSE(stream.wait(&r).ok());  // nothing in flight
  EXPECT_FALSE(stream.poll(&r));
  const cv::Mat half = frame(cv::Rect(0, 0, frame.cols / 2, frame.rows));
  const ellipsekit::Status wrong = stream.submit(View(half), 0);
  EXPECT_FALSE(wrong.ok());
  EXPECT_NE(wrong.message().find("differs from the stream's"), std::string::npos) << wrong.message();
  EXPECT_FALSE(stream.submit({nullptr, frame.cols, frame.rows, frame.cols}, 0).ok());
  EXPECT_EQ(stream.in_flight(), 0);
  ASSERT_TRUE(stream.submit(View(frame), 1).ok());
  ASSERT_TRUE(stream.submit(View(frame), 2).ok());
  const ellipsekit::Status full = stream.submit(View(frame), 3);
  EXPECT_FALSE(full.ok());
  EXPECT_NE(full.message().find("stream full"), std::string::npos) << full.message();
  ASSERT_TRUE(stream.wait(&r).ok());
  EXPECT_EQ(r.tag, 1u);
  // A strided view (a column band of a wider frame) is copied row by row.
  cv::Mat wide(frame.rows, frame.cols + 40, CV_8UC1, cv::Scalar(0));
  frame.copyTo(wide(cv::Rect(20, 0, frame.cols, frame.rows)));
  ASSERT_TRUE(stream.submit(View(wide(cv::Rect(20, 0, frame.cols, frame.rows))), 4).ok());
  ASSERT_TRUE(stream.wait(&r).ok());
  EXPECT_EQ(r.tag, 2u);
  ellipsekit::StreamResult strided;
  ASSERT_TRUE(stream.wait(&strided).ok());
  EXPECT_EQ(strided.tag, 4u);
  ASSERT_EQ(strided.result.ellipses.size(), r.result.ellipses.size());
  for (std::size_t i = 0; i < r.result.ellipses.size(); ++i) EXPECT_EQ(strided.result.ellipses[i].cx, r.result.ellipses[i].cx);
  // Destroyed with a frame in flight: no hang, no leak (the sanitizer build checks).
  ASSERT_TRUE(stream.submit(View(frame), 5).ok());
}

}  // namespace
