// Robot adapter: Hungarian assignment, Kalman filter, multi-ellipse tracking, stacking regions.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "ellipsekit/robot/hungarian.h"
#include "ellipsekit/robot/kalman.h"
#include "ellipsekit/robot/stacking.h"
#include "ellipsekit/robot/tracker.h"
#include "robot/testing/synthetic.h"

namespace er = ellipsekit::robot;
namespace st = ellipsekit::robot::testing;
using ellipsekit::Ellipse;

TEST(RobotHungarian, MatchesBruteForce) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 10);
  for (int trial = 0; trial < 300; ++trial) {
    const int rows = 1 + trial % 6, cols = 1 + (trial / 6) % 6;
    Eigen::MatrixXd c(rows, cols);
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j) c(i, j) = std::floor(u(rng));
    const std::vector<int> a = er::SolveAssignment(c);
    double got = 0;
    std::set<int> used;
    int assigned = 0;
    for (int i = 0; i < rows; ++i) {
      if (a[i] >= 0) {
        got += c(i, a[i]);
        EXPECT_TRUE(used.insert(a[i]).second);
        ++assigned;
      }
    }
    EXPECT_EQ(assigned, std::min(rows, cols));
    // Brute force over injections of the smaller side.
    double best = 1e300;
    const int n = std::min(rows, cols), m = std::max(rows, cols);
    std::vector<int> perm(m);
    std::iota(perm.begin(), perm.end(), 0);
    do {
      double s = 0;
      for (int k = 0; k < n; ++k) s += rows <= cols ? c(k, perm[k]) : c(perm[k], k);
      best = std::min(best, s);
    } while (std::next_permutation(perm.begin(), perm.end()));
    EXPECT_NEAR(got, best, 1e-9);
  }
  // Forbidden entries stay unassigned.
  Eigen::MatrixXd c(2, 2);
  c << 1, 1e18, 1e18, 1e18;
  const std::vector<int> a = er::SolveAssignment(c, 1e18);
  EXPECT_EQ(a[0], 0);
  EXPECT_EQ(a[1], -1);
}

TEST(RobotKalman, ConvergesToConstantVelocity) {
  er::ConstantVelocityKalman kf(Eigen::Vector2d(0, 0), 1, 1e4, 10, 0.25);
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0, 0.5);
  double t = 0;
  for (int i = 0; i < 90; ++i) {
    t += 1.0 / 30;
    kf.Predict(1.0 / 30);
    kf.Update(Eigen::Vector2d(100 * t + g(rng), -40 * t + g(rng)));
  }
  EXPECT_NEAR(kf.velocity()(0), 100, 5);
  EXPECT_NEAR(kf.velocity()(1), -40, 5);
  EXPECT_NEAR(kf.position()(0), 100 * t, 1);
  EXPECT_LT(kf.Mahalanobis2(Eigen::Vector2d(100 * t, -40 * t)), 9);
}

namespace {

// Two cans moving on the table in opposite directions; their tops cross in the image.
struct CrossingResult {
  int id_switches = 0;
  int frames = 0;
  std::vector<std::set<std::int64_t>> ids;
};

CrossingResult RunCrossing(double y_a, double y_b, double height_b, double speed, unsigned seed) {
  const er::CameraModel cam = st::KinectCamera();
  const st::CameraPose pose = st::LookAt({0, -0.6, 1.5}, {0, 0.4, 0.75});
  const Eigen::Vector3d up = pose.DirToCamera(Eigen::Vector3d::UnitZ());
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  er::EllipseTracker tracker;
  CrossingResult r;
  r.ids.resize(2);
  std::vector<std::int64_t> last_id(2, -1);
  const double duration = 0.8 / speed;
  for (int f = 0; f * (1.0 / 30) <= duration; ++f) {
    const double t = f / 30.0;
    st::Can a, b;
    a.bottom = {-0.4 + speed * t, y_a, 0.75};
    b.bottom = {0.4 - speed * t, y_b, 0.75};
    b.height = height_b;
    std::vector<Ellipse> dets;
    std::vector<int> truth;
    std::vector<Eigen::Vector2d> px;
    for (const st::Can* c : {&a, &b}) px.push_back(cam.Project(pose.ToCamera(c->TopCentre())).value);
    const bool overlap = (px[0] - px[1]).norm() < 20;
    for (int k = 0; k < 2; ++k) {
      const st::Can& c = k == 0 ? a : b;
      if (u(rng) < 0.05) continue;                   // missed detection
      if (overlap && c.height < 0.13 && k == 0 && height_b > 0.13) continue;  // lower top hidden
      dets.push_back(st::NoisyEllipse(cam, pose.ToCamera(c.TopCentre()), up, c.radius, 1.0, rng));
      truth.push_back(k);
    }
    // Detector order is arbitrary.
    if (u(rng) < 0.5 && dets.size() == 2) {
      std::swap(dets[0], dets[1]);
      std::swap(truth[0], truth[1]);
    }
    EXPECT_TRUE(tracker.Update(dets, t).ok());
    for (const er::Track& tr : tracker.tracks()) {
      if (tr.state != er::TrackState::kConfirmed || tr.detection_index < 0) continue;
      const int k = truth[tr.detection_index];
      r.ids[k].insert(tr.id);
      if (last_id[k] >= 0 && last_id[k] != tr.id) ++r.id_switches;
      last_id[k] = tr.id;
    }
    ++r.frames;
  }
  return r;
}

}  // namespace

// Done-when: track ids of a can stay the same across the whole run; no id switches when two cans cross.
TEST(RobotTracker, NoIdSwitchWhenTwoCansCross) {
  int total_switches = 0, runs = 0;
  for (double speed : {0.025, 0.05, 0.10, 0.20}) {
    for (unsigned seed : {1u, 2u, 3u}) {
      // Side by side (6 cm apart across the table), and on one line with one can taller (tops
      // overlap in the image; the lower one is hidden at the crossing).
      for (int scenario = 0; scenario < 2; ++scenario) {
        const CrossingResult r = scenario == 0 ? RunCrossing(0.40, 0.46, 0.12, speed, seed)
                                               : RunCrossing(0.40, 0.40, 0.20, speed, seed);
        EXPECT_EQ(r.ids[0].size(), 1u) << "speed " << speed << " scenario " << scenario;
        EXPECT_EQ(r.ids[1].size(), 1u) << "speed " << speed << " scenario " << scenario;
        if (r.ids[0].size() == 1 && r.ids[1].size() == 1) EXPECT_NE(*r.ids[0].begin(), *r.ids[1].begin());
        total_switches += r.id_switches;
        ++runs;
      }
    }
  }
  std::cout << "[robot] crossing cans: " << runs << " runs (4 speeds x 3 seeds x 2 layouts), id switches "
            << total_switches << "\n";
  RecordProperty("crossing_id_switches", std::to_string(total_switches));
  EXPECT_EQ(total_switches, 0);
}

TEST(RobotTracker, StatesAndErrors) {
  er::EllipseTracker tr;
  const Ellipse e{100, 100, 20, 10, 0, 1};
  ASSERT_TRUE(tr.Update({e}, 0.0).ok());
  EXPECT_EQ(tr.tracks()[0].state, er::TrackState::kTentative);
  ASSERT_TRUE(tr.Update({e}, 0.033).ok());
  ASSERT_TRUE(tr.Update({e}, 0.066).ok());
  EXPECT_EQ(tr.tracks()[0].state, er::TrackState::kConfirmed);
  const auto id = tr.tracks()[0].id;
  ASSERT_TRUE(tr.Update({}, 0.1).ok());
  EXPECT_EQ(tr.tracks()[0].state, er::TrackState::kLost);
  ASSERT_TRUE(tr.Update({e}, 0.2).ok());
  EXPECT_EQ(tr.tracks()[0].id, id);
  EXPECT_EQ(tr.tracks()[0].state, er::TrackState::kConfirmed);
  ASSERT_TRUE(tr.Update({}, 0.5).ok());
  ASSERT_TRUE(tr.Update({}, 0.8).ok());  // lost for > max_lost_s: deleted
  EXPECT_TRUE(tr.tracks().empty());
  EXPECT_FALSE(tr.Update({e}, 0.8).ok());  // time must increase
  Ellipse bad = e;
  bad.a = std::nan("");
  EXPECT_FALSE(tr.Update({bad}, 1.0).ok());
}

// Stacking task (paper sec. V-A): a new can on the feed side (right) is carried to the stack
// side (left): same id, its role changes, and it becomes the next stacking target; a second can
// stacked on it becomes the new target.
TEST(RobotStacking, RegionStatesAndNextTarget) {
  const er::CameraModel cam = st::KinectCamera();
  const st::CameraPose pose = st::LookAt({0, -0.6, 1.5}, {0, 0.4, 0.75});
  const Eigen::Vector3d up = pose.DirToCamera(Eigen::Vector3d::UnitZ());
  auto px = [&](Eigen::Vector3d w) { return cam.Project(pose.ToCamera(w)).value; };
  er::StackingRegions regions{px({0, 0.2, 0.75}), px({0, 0.8, 0.75}), px({0.3, 0.4, 0.75})};
  er::StackingMonitor monitor(regions);
  er::EllipseTracker tracker;
  std::mt19937 rng(9);
  std::vector<er::StackingEvent> events;
  // Can 1: appears at x = 0.3 (t 0..1 s), carried to x = -0.3 (t 1..3 s), rests there.
  // Can 2: appears at x = 0.3 at t = 4 s, lifted by 12 cm (t 4.5..5 s), carried onto can 1
  // (t 5..7 s), then hides can 1's top.
  for (int f = 0; f < 9 * 30; ++f) {
    const double t = f / 30.0;
    std::vector<Ellipse> dets;
    st::Can c1, c2;
    const double x1 = t < 1 ? 0.3 : (t < 3 ? 0.3 - 0.3 * (t - 1) : -0.3);
    c1.bottom = {x1, 0.45, 0.75};
    const double x2 = t < 5 ? 0.3 : (t < 7 ? 0.3 - 0.3 * (t - 5) : -0.3);
    c2.bottom = {x2, 0.45, 0.75 + 0.12 * std::clamp((t - 4.5) / 0.5, 0.0, 1.0)};  // lifted, then carried
    const bool c2_on_top = t >= 7;
    if (!c2_on_top) dets.push_back(st::NoisyEllipse(cam, pose.ToCamera(c1.TopCentre()), up, c1.radius, 1.0, rng));
    if (t >= 4) dets.push_back(st::NoisyEllipse(cam, pose.ToCamera(c2.TopCentre()), up, c2.radius, 1.0, rng));
    ASSERT_TRUE(tracker.Update(dets, t).ok());
    for (const auto& e : monitor.Update(tracker.tracks(), t)) events.push_back(e);
  }
  std::vector<std::string> log;
  for (const auto& e : events) {
    static const char* names[] = {"new", "stacked", "target"};
    log.push_back(std::string(names[e.kind]) + ":" + std::to_string(e.track_id));
  }
  std::string joined;
  for (const auto& s : log) joined += s + " ";
  std::cout << "[robot] stacking events: " << joined << "\n";
  // Expected: new:A stacked:A target:A new:B stacked:B target:B (A's track ends under B).
  ASSERT_GE(events.size(), 6u);
  const auto a = events[0].track_id;
  EXPECT_EQ(events[0].kind, er::StackingEvent::kNewObject);
  EXPECT_EQ(events[1].kind, er::StackingEvent::kObjectStacked);
  EXPECT_EQ(events[1].track_id, a);
  EXPECT_EQ(events[2].kind, er::StackingEvent::kTargetChanged);
  EXPECT_EQ(events[2].track_id, a);
  EXPECT_EQ(events[3].kind, er::StackingEvent::kNewObject);
  const auto b = events[3].track_id;
  EXPECT_NE(a, b);
  auto target = monitor.NextStackingTarget();
  ASSERT_TRUE(target.has_value());
  EXPECT_EQ(target->track_id, b);
  EXPECT_TRUE(monitor.NewObjects().empty());
}
