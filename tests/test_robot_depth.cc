// Robot adapter: 3-D top centre from the registered depth image, averaged over 20 detections
// (paper sec. V-A), on a synthetic static stacking scene.
#include <gtest/gtest.h>

#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "ellipsekit/robot/depth_sampling.h"
#include "robot/testing/synthetic.h"

namespace er = ellipsekit::robot;
namespace st = ellipsekit::robot::testing;
using ellipsekit::Ellipse;

TEST(RobotDepth, RejectsBadInput) {
  const er::CameraModel cam = st::KinectCamera();
  Ellipse e{320, 240, 20, 10, 0, 0};
  EXPECT_FALSE(er::SampleTopCentre(e, er::DepthImageView{}, cam).ok());  // empty view
  std::vector<std::uint16_t> zeros(640 * 480, 0);
  er::DepthImageView v{zeros.data(), 640, 480, 640 * 2, er::DepthEncoding::k16UC1};
  EXPECT_FALSE(er::SampleTopCentre(e, v, cam).ok());  // no valid depth
  e.b = 0;
  EXPECT_FALSE(er::SampleTopCentre(e, v, cam).ok());  // degenerate
  er::CentreAverager avg;
  EXPECT_FALSE(avg.Estimate().ok());
}

TEST(RobotDepth, Float32MetresWithNaN) {
  const er::CameraModel cam = st::KinectCamera();
  std::vector<float> z(640 * 480, 1.25f);
  for (std::size_t i = 0; i < z.size(); i += 3) z[i] = std::numeric_limits<float>::quiet_NaN();
  er::DepthImageView v{z.data(), 640, 480, 640 * 4, er::DepthEncoding::k32FC1};
  auto s = er::SampleTopCentre(Ellipse{319.5, 239.5, 30, 20, 0.3, 0}, v, cam);
  ASSERT_TRUE(s.ok()) << s.status.message();
  EXPECT_NEAR(s.value.median_depth_m, 1.25, 1e-6);
  EXPECT_NEAR(s.value.centre.x(), 0, 1e-9);
  EXPECT_LT(s.value.valid_samples, s.value.total_samples);
}

// Done-when: static stacking scene, 20 detections averaged: 3-D top-centre error <= 3 mm median.
TEST(RobotDepth, StaticStackingSceneTwentyDetections) {
  const er::CameraModel cam = st::KinectCamera();
  // Kinect ~1.5 m above the floor looking down at a table (top at z = 0.75 m), world z up.
  const st::CameraPose pose = st::LookAt({0, -0.6, 1.5}, {0, 0.4, 0.75});
  const double table = 0.75;
  std::vector<st::Can> cans;
  // Feed side (right): single cans; stack side (left): a stack of two and a single can.
  for (Eigen::Vector3d b : {Eigen::Vector3d(0.25, 0.3, table), Eigen::Vector3d(0.32, 0.55, table),
                            Eigen::Vector3d(0.15, 0.75, table), Eigen::Vector3d(-0.25, 0.45, table),
                            Eigen::Vector3d(-0.30, 0.25, table)}) {
    st::Can c;
    c.bottom = b;
    cans.push_back(c);
  }
  st::Can top_of_stack;
  top_of_stack.bottom = cans[3].TopCentre();
  cans.push_back(top_of_stack);
  const std::vector<int> visible_tops = {0, 1, 2, 4, 5};  // can 3 is covered by can 5

  const std::vector<float> clean = st::RenderDepth(cam, pose, table, cans);
  std::mt19937 rng(42);
  const Eigen::Vector3d up_cam = pose.DirToCamera(Eigen::Vector3d::UnitZ());
  std::vector<er::CentreAverager> with_normal(cans.size()), plain(cans.size());
  std::vector<double> single_err;
  for (int frame = 0; frame < 20; ++frame) {
    const std::vector<std::uint16_t> depth = st::DegradeDepth(clean, rng);
    const er::DepthImageView view{depth.data(), 640, 480, 640 * 2, er::DepthEncoding::k16UC1};
    for (int k : visible_tops) {
      const Eigen::Vector3d top_c = pose.ToCamera(cans[k].TopCentre());
      const Ellipse e = st::NoisyEllipse(cam, top_c, up_cam, cans[k].radius, 1.0, rng);
      er::DepthSampleOptions opt;
      opt.plane_normal = up_cam;  // the table normal in the camera frame (cans stand upright)
      auto s = er::SampleTopCentre(e, view, cam, opt);
      ASSERT_TRUE(s.ok()) << s.status.message();
      with_normal[k].Add(s.value.centre);
      single_err.push_back((s.value.centre - top_c).norm());
      auto s2 = er::SampleTopCentre(e, view, cam);
      ASSERT_TRUE(s2.ok());
      plain[k].Add(s2.value.centre);
    }
  }
  std::vector<double> err_mm, err_plain_mm;
  for (int k : visible_tops) {
    const Eigen::Vector3d truth = pose.ToCamera(cans[k].TopCentre());
    auto a = with_normal[k].Estimate();
    ASSERT_TRUE(a.ok());
    EXPECT_EQ(a.value.inliers + a.value.outliers, 20);
    err_mm.push_back(1000 * (a.value.mean - truth).norm());
    err_plain_mm.push_back(1000 * (plain[k].Estimate().value.mean - truth).norm());
    // The reported covariance is consistent with the error (within ~5 sigma plus 1 mm of bias).
    const double sigma = std::sqrt(a.value.covariance.trace());
    EXPECT_LT((a.value.mean - truth).norm(), 5 * sigma + 0.001);
  }
  const double med = st::Percentile(err_mm, 50);
  std::cout << "[robot] static stacking scene, 20 detections averaged: top-centre error mm median " << med
            << " max " << st::Percentile(err_mm, 100) << " (without the plane-normal centre correction: median "
            << st::Percentile(err_plain_mm, 50) << " max " << st::Percentile(err_plain_mm, 100)
            << "); single-detection error mm median " << 1000 * st::Percentile(single_err, 50) << "\n";
  RecordProperty("top_centre_error_mm_median", std::to_string(med));
  EXPECT_LE(med, 3.0);
}

TEST(RobotDepth, AveragerRejectsOutliers) {
  er::CentreAverager avg;
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0, 0.001);
  for (int i = 0; i < 17; ++i) avg.Add(Eigen::Vector3d(0.1 + g(rng), 0.2 + g(rng), 1.0 + g(rng)));
  avg.Add(Eigen::Vector3d(0.1, 0.2, 1.5));  // missing depth read as the floor
  avg.Add(Eigen::Vector3d(0.3, 0.2, 1.0));
  avg.Add(Eigen::Vector3d(0.1, 0.0, 0.9));
  auto e = avg.Estimate();
  ASSERT_TRUE(e.ok());
  EXPECT_EQ(e.value.outliers, 3);
  EXPECT_LT((e.value.mean - Eigen::Vector3d(0.1, 0.2, 1.0)).norm(), 0.001);
  auto m = avg.EstimateStamped(er::Header{er::Time::FromSeconds(1.5), "camera_color_optical_frame"});
  ASSERT_TRUE(m.ok());
  EXPECT_GT(m.value.covariance[0], 0);
  EXPECT_EQ(m.value.covariance[1], m.value.covariance[3]);
}
