// The robot loop's hot-path contract (include/ellipsekit/robot/frame_loop.h): after the first frame,
// FrameLoop::ProcessFrame() -- detect, track, 3-D rim centres, conveyor, grasp -- allocates nothing.
//
// Allocations are counted by tests/alloc_counter.h (the C allocator interposed: operator new and
// every library's allocations count) while the call under test runs; the detector runs on the
// SIMD backend (no Vulkan driver threads). The first few keep a backtrace, printed on failure.
// Frames come from the scene generator (ray-cast images and depth of real container geometry),
// rendered before counting starts.
//
// Not under AddressSanitizer or ThreadSanitizer (whose runtime owns malloc): the suite skips there.
#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "ellipsekit/robot/circle_pose.h"
#include "ellipsekit/robot/frame_loop.h"
#include "tests/alloc_counter.h"
#include "tests/robot_test_util.h"
#include "tools/scenes/scene_generator.h"

namespace {

namespace er = ellipsekit::robot;
namespace sc = ellipsekit::scenes;

using Count = ellipsekit::test::AllocationCount;
using ellipsekit::test::DepthView;
using ellipsekit::test::View;
using ellipsekit::test::CountAllocations;
using ellipsekit::test::PrintAllocationTraces;

// One rendered frame, owned.
struct Frame {
  double t = 0;
  cv::Mat gray, depth_mm;
};

struct Sequence {
  er::CameraModel camera;
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  std::vector<Frame> frames;
  std::vector<int> truths;  // true tops per frame
  std::optional<std::array<er::ConveyorReference, 2>> conveyor;
};

template <class Info>
void SetRig(const Info& info, Sequence* s) {
  s->camera = er::CameraModel::FromIntrinsics(info.K(0, 0), info.K(1, 1), info.K(0, 2), info.K(1, 2), {}, info.width,
                                              info.height);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) s->T(r, c) = info.T_world_camera(r, c);
}

Eigen::Vector3d ToCamera(const Eigen::Matrix4d& T, const cv::Vec3d& w) {
  return T.topLeftCorner<3, 3>().transpose() * (Eigen::Vector3d(w[0], w[1], w[2]) - T.topRightCorner<3, 1>());
}

// A can (recessed lid) riding the guide: the conveyor model and the grasp planner run too.
Sequence ConveyorSequence(int frames) {
  sc::ConveyorSceneOptions co;
  co.speed_m_s = 0.05;
  co.frames = frames;
  co.container = sc::Container::kRecessedCan;
  sc::ConveyorSequence info;
  Sequence s;
  EXPECT_TRUE(sc::RenderConveyorSequence(11, co, &info, [&](const sc::ConveyorFrame& f) {
                s.frames.push_back({f.t, f.gray.clone(), f.depth_mm.clone()});
                s.truths.push_back(1);
                return ellipsekit::Status::Ok();
              }).ok());
  SetRig(info, &s);
  std::array<er::ConveyorReference, 2> refs;
  refs[0].point = Eigen::Vector3d(info.start_point[0], info.start_point[1], info.start_point[2]);
  refs[0].pixel = Eigen::Vector2d(info.start_pixel[0], info.start_pixel[1]);
  refs[0].camera_depth_z = ToCamera(s.T, info.start_point).z();
  refs[1].point = Eigen::Vector3d(info.end_point[0], info.end_point[1], info.end_point[2]);
  refs[1].pixel = Eigen::Vector2d(info.end_pixel[0], info.end_pixel[1]);
  refs[1].camera_depth_z = ToCamera(s.T, info.end_point).z();
  s.conveyor = refs;
  return s;
}

// Two containers (open cup, jar, ...) standing or crossing: two tracks, births and deaths.
Sequence CanSequence(std::uint64_t seed, sc::Container c0, sc::Container c1, double speed, int frames) {
  sc::CanSceneOptions co;
  co.frames = frames;
  co.speed_m_s = speed;
  co.containers = {c0, c1};
  sc::CanSequence info;
  Sequence s;
  EXPECT_TRUE(sc::RenderCanSequence(seed, co, &info, [&](const sc::CanFrame& f) {
                s.frames.push_back({f.t, f.gray.clone(), f.depth_mm.clone()});
                s.truths.push_back(2);
                return ellipsekit::Status::Ok();
              }).ok());
  SetRig(info, &s);
  return s;
}

enum class DepthMode { kRimPlane, kInterior, kNone };

// Runs the sequence through one FrameLoop: the first frame uncounted, every later one counted.
// Expects zero allocations per later frame, and that the loop did its work (tracks with 3-D
// positions; a grasp decision on the conveyor).
void ExpectNoAllocationPerFrame(const Sequence& s, DepthMode mode, const char* what) {
  if (!ellipsekit::test::kCountsAllocations) GTEST_SKIP() << "the sanitizer's runtime owns malloc; counted in the plain build";
  ASSERT_GE(s.frames.size(), 3u);
  er::FrameLoopOptions opt;
  opt.detector.backend = ellipsekit::Backend::kSimd;
  opt.T_world_camera = s.T;
  opt.conveyor = s.conveyor;
  opt.grasp.latency_s = 0.5;
  opt.top_centre = mode == DepthMode::kInterior ? er::TopCentreMethod::kInteriorMedian : er::TopCentreMethod::kRimPlane;
  opt.top_radius_m = 0.033;  // the circle pose where depth is missing or fails
  er::FrameLoop loop(s.camera, opt);
  if (!loop.status().ok() && opt.detector.backend == ellipsekit::Backend::kSimd)
    GTEST_SKIP() << "no SIMD backend: " << loop.status().message();
  er::FrameOutput out;
  long total = 0, worst = 0;
  int with_position = 0, grasps = 0, from_mode = 0;
  const er::CentreSource expected = mode == DepthMode::kRimPlane   ? er::CentreSource::kRimPlane
                                    : mode == DepthMode::kInterior ? er::CentreSource::kInteriorMedian
                                                                   : er::CentreSource::kCirclePose;
  for (std::size_t i = 0; i < s.frames.size(); ++i) {
    const Frame& f = s.frames[i];
    const er::DepthImageView dv = DepthView(f.depth_mm);
    const er::DepthImageView* dp = mode == DepthMode::kNone ? nullptr : &dv;
    ellipsekit::Status st;
    const Count c = CountAllocations([&] { st = loop.ProcessFrame(View(f.gray), dp, f.t, &out); });
    ASSERT_TRUE(st.ok()) << st.message();
    for (const er::TrackOutput& t : out.tracks) {
      with_position += t.detected && t.has_position;
      from_mode += t.detected && t.source == expected;
    }
    grasps += out.grasp.plan.decision == er::GraspDecision::kGrasp;
    if (i == 0) {
      std::printf("[robot-alloc] %s: first frame %ld allocations (%ld bytes)\n", what, c.allocations, c.bytes);
      // The first frame sizes the loop's buffers: none counted would mean the counter is not linked in
      // (tests/alloc_counter.h's own check is NoAllocation.CounterSeesAllocations).
      EXPECT_GT(c.allocations, 0) << what << ": the first frame allocated nothing: is the counter linked in?";
      continue;
    }
    total += c.allocations;
    worst = std::max(worst, c.allocations);
    if (c.allocations != 0) {
      std::fprintf(stderr, "ALLOCATION FOUND: %s, frame %zu: ProcessFrame allocated %ld times (%ld bytes); first "
                           "backtraces:\n", what, i, c.allocations, c.bytes);
      PrintAllocationTraces();
    }
    EXPECT_EQ(c.allocations, 0) << what << ", frame " << i << ": ProcessFrame allocated after the first frame";
  }
  std::printf("[robot-alloc] %s: frames 2-%zu: %ld allocations in all (%.2f per frame, worst frame %ld); %d track "
              "outputs with a 3-D position, %d frames with a grasp decision\n",
              what, s.frames.size(), total, static_cast<double>(total) / static_cast<double>(s.frames.size() - 1),
              worst, with_position, grasps);
  // The loop did its work: most frames give every top a 3-D position; the conveyor plans grasps.
  int tops = 0;
  for (int n : s.truths) tops += n;
  EXPECT_GE(with_position, tops / 2) << what;
  EXPECT_GE(from_mode, with_position / 2) << what << ": the centres should come from " << er::CentreSourceName(expected);
  if (s.conveyor) EXPECT_GT(grasps, 0) << what;
}

TEST(RobotNoAllocation, ConveyorRecessedCanRimPlane) {
  ExpectNoAllocationPerFrame(ConveyorSequence(24), DepthMode::kRimPlane, "conveyor, recessed can, rim plane");
}

TEST(RobotNoAllocation, ConveyorInteriorMedian) {
  ExpectNoAllocationPerFrame(ConveyorSequence(16), DepthMode::kInterior, "conveyor, interior median");
}

TEST(RobotNoAllocation, ConveyorNoDepthCirclePose) {
  ExpectNoAllocationPerFrame(ConveyorSequence(16), DepthMode::kNone, "conveyor, no depth (circle pose)");
}

TEST(RobotNoAllocation, StaticCupAndJar) {
  ExpectNoAllocationPerFrame(CanSequence(102, sc::Container::kCupEmpty, sc::Container::kJar, 0, 8), DepthMode::kRimPlane,
                             "static cup + jar");
}

TEST(RobotNoAllocation, CrossingFilledCupAndRecessedCan) {
  ExpectNoAllocationPerFrame(CanSequence(22, sc::Container::kCupFilled, sc::Container::kRecessedCan, 0.1, 20),
                             DepthMode::kRimPlane, "crossing filled cup + recessed can, 10 cm/s");
}

// The circle pose through lens distortion (the boundary is undistorted and refit in fixed storage).
TEST(RobotNoAllocation, CirclePoseWithDistortion) {
  if (!ellipsekit::test::kCountsAllocations) GTEST_SKIP() << "the sanitizer's runtime owns malloc";
  const er::CameraModel cam =
      er::CameraModel::FromIntrinsics(525, 525, 319.5, 239.5, {0.12, -0.25, 0.001, -0.002, 0.08}, 640, 480);
  ellipsekit::Ellipse e;
  e.cx = 400;
  e.cy = 300;
  e.a = 30;
  e.b = 18;
  e.theta = 0.2;
  bool ok = false;
  const Count c = CountAllocations([&] { ok = er::CirclePoseByNormal(e, 0.033, cam, Eigen::Vector3d(0, -0.7, -0.7)).ok(); });
  ASSERT_TRUE(ok);
  if (c.allocations != 0) PrintAllocationTraces();
  EXPECT_EQ(c.allocations, 0) << "CirclePoseByNormal with distortion allocated";
}

}  // namespace
