// The scene generator (tools/scenes): conic conversion, ground truth against the rendered edges,
// determinism, dataset files, argument checks, and the conveyor sequence's ground truth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "tools/scenes/conic.h"
#include "tools/scenes/scene_generator.h"

namespace {

using ellipsekit::Ellipse;
namespace sc = ellipsekit::scenes;
namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;

fs::path TempDir(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("ellipsekit_test_scenes_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  return p;
}

// --------------------------------------------------------------- conics
TEST(SceneConic, CircleAtOffset) {
  // (x - 10)^2 + (y + 4)^2 = 9
  const cv::Matx33d q(1, 0, -10, 0, 1, 4, -10, 4, 100 + 16 - 9);
  Ellipse e;
  ASSERT_TRUE(sc::ConicToEllipse(q, &e));
  EXPECT_NEAR(e.cx, 10, 1e-9);
  EXPECT_NEAR(e.cy, -4, 1e-9);
  EXPECT_NEAR(e.a, 3, 1e-9);
  EXPECT_NEAR(e.b, 3, 1e-9);
  EXPECT_EQ(e.score, 0);
}

TEST(SceneConic, AxisAlignedEllipseAnyScaleAndSign) {
  // (x - 3)^2 / 25 + (y - 7)^2 / 4 = 1, scaled by -2.5.
  const double A = 1.0 / 25, C = 1.0 / 4;
  cv::Matx33d q(A, 0, -3 * A, 0, C, -7 * C, -3 * A, -7 * C, 9 * A + 49 * C - 1);
  q *= -2.5;
  Ellipse e;
  ASSERT_TRUE(sc::ConicToEllipse(q, &e));
  EXPECT_NEAR(e.cx, 3, 1e-9);
  EXPECT_NEAR(e.cy, 7, 1e-9);
  EXPECT_NEAR(e.a, 5, 1e-9);
  EXPECT_NEAR(e.b, 2, 1e-9);
  EXPECT_NEAR(e.theta, 0, 1e-9);
  // Major axis vertical: theta = -pi/2 (the range is [-pi/2, pi/2)).
  const cv::Matx33d qv(C, 0, -3 * C, 0, A, -7 * A, -3 * C, -7 * A, 9 * C + 49 * A - 1);
  ASSERT_TRUE(sc::ConicToEllipse(qv, &e));
  EXPECT_NEAR(e.a, 5, 1e-9);
  EXPECT_NEAR(e.b, 2, 1e-9);
  EXPECT_NEAR(std::abs(e.theta), kPi / 2, 1e-9);
}

TEST(SceneConic, RotatedEllipseRoundTrip) {
  for (double theta : {-1.2, -0.4, 0.0, 0.3, 0.9, 1.5}) {
    Ellipse in;
    in.cx = 120.5;
    in.cy = -33.25;
    in.a = 40;
    in.b = 17;
    in.theta = theta;
    const cv::Matx33d q = sc::EllipseToConic(in);
    // A point on the ellipse satisfies the conic.
    const double t = 0.7;
    const double x = in.cx + in.a * std::cos(t) * std::cos(theta) - in.b * std::sin(t) * std::sin(theta);
    const double y = in.cy + in.a * std::cos(t) * std::sin(theta) + in.b * std::sin(t) * std::cos(theta);
    const cv::Vec3d p(x, y, 1);
    EXPECT_NEAR(p.dot(q * p), 0, 1e-9);
    Ellipse out;
    ASSERT_TRUE(sc::ConicToEllipse(q, &out));
    EXPECT_NEAR(out.cx, in.cx, 1e-8);
    EXPECT_NEAR(out.cy, in.cy, 1e-8);
    EXPECT_NEAR(out.a, in.a, 1e-8);
    EXPECT_NEAR(out.b, in.b, 1e-8);
    EXPECT_NEAR(out.theta, sc::NormalizeAxisAngle(theta), 1e-9);
  }
}

TEST(SceneConic, RejectsNonEllipses) {
  Ellipse e;
  e.cx = 42;
  EXPECT_FALSE(sc::ConicToEllipse(cv::Matx33d(1, 0, 0, 0, -1, 0, 0, 0, -1), &e));   // hyperbola
  EXPECT_FALSE(sc::ConicToEllipse(cv::Matx33d(1, 0, 0, 0, 1, 0, 0, 0, 1), &e));     // imaginary
  EXPECT_FALSE(sc::ConicToEllipse(cv::Matx33d(1, 0, 0, 0, 0, -0.5, 0, -0.5, 0), &e));  // parabola
  EXPECT_FALSE(sc::ConicToEllipse(cv::Matx33d(1, 0, 0, 0, 1, 0, 0, 0, 0), &e));     // a point
  EXPECT_FALSE(sc::ConicToEllipse(cv::Matx33d(NAN, 0, 0, 0, 1, 0, 0, 0, -1), &e));
  EXPECT_EQ(e.cx, 42);  // left alone
}

TEST(SceneConic, ProjectedCircleSeenHeadOn) {
  // Camera 2 m above a circle of radius 0.5 m at the origin, looking straight at it: a circle of
  // radius f r / d around the principal point.
  const double f = 500;
  const cv::Matx33d K(f, 0, 320, 0, f, 240, 0, 0, 1);
  const cv::Matx33d R = cv::Matx33d::eye();
  const cv::Vec3d t(0, 0, 2);
  const cv::Matx33d q = sc::ProjectCircleConic(K, R, t, cv::Vec3d(0, 0, 0), cv::Vec3d(1, 0, 0), cv::Vec3d(0, 1, 0), 0.5);
  Ellipse e;
  ASSERT_TRUE(sc::ConicToEllipse(q, &e));
  EXPECT_NEAR(e.cx, 320, 1e-9);
  EXPECT_NEAR(e.cy, 240, 1e-9);
  EXPECT_NEAR(e.a, f * 0.5 / 2, 1e-9);
  EXPECT_NEAR(e.b, f * 0.5 / 2, 1e-9);
  // Offset circle: centre projects to K (X/Z, Y/Z).
  const cv::Matx33d q2 =
      sc::ProjectCircleConic(K, R, t, cv::Vec3d(0.4, -0.2, 0), cv::Vec3d(1, 0, 0), cv::Vec3d(0, 1, 0), 0.1);
  ASSERT_TRUE(sc::ConicToEllipse(q2, &e));
  EXPECT_NEAR(e.cx, 320 + f * 0.4 / 2, 1e-9);
  EXPECT_NEAR(e.cy, 240 - f * 0.2 / 2, 1e-9);
  EXPECT_NEAR(e.a, f * 0.1 / 2, 1e-9);
}

// --------------------------------------------------------------- rendered edges lie on the truth
double MeanGradientAlong(const cv::Mat& mag, const Ellipse& e, double scale) {
  double sum = 0;
  int n = 0;
  const double c = std::cos(e.theta), s = std::sin(e.theta);
  for (int k = 0; k < 720; ++k) {
    const double t = 2 * kPi * k / 720;
    const double x = e.cx + scale * (e.a * std::cos(t) * c - e.b * std::sin(t) * s);
    const double y = e.cy + scale * (e.a * std::cos(t) * s + e.b * std::sin(t) * c);
    const int xi = static_cast<int>(std::lround(x)), yi = static_cast<int>(std::lround(y));
    if (xi < 1 || yi < 1 || xi >= mag.cols - 1 || yi >= mag.rows - 1) continue;
    sum += mag.at<float>(yi, xi);
    ++n;
  }
  return n ? sum / n : 0;
}

TEST(SceneGenerator, RenderedEdgesLieOnTruth) {
  sc::SceneOptions opt;
  opt.occlusion = false;  // full rims
  double sum_gt = 0, sum_in = 0, sum_out = 0;
  int tops = 0, wins = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    const sc::Scene scene = sc::RenderScene(sc::MixSeed(99, seed), opt);
    ASSERT_FALSE(scene.gray.empty());
    cv::Mat gx, gy, mag;
    cv::Sobel(scene.gray, gx, CV_32F, 1, 0, 3);
    cv::Sobel(scene.gray, gy, CV_32F, 0, 1, 3);
    cv::magnitude(gx, gy, mag);
    for (const Ellipse& e : scene.truth) {
      const double g = MeanGradientAlong(mag, e, 1.0), gi = MeanGradientAlong(mag, e, 0.8),
                   go = MeanGradientAlong(mag, e, 1.2);
      sum_gt += g;
      sum_in += gi;
      sum_out += go;
      ++tops;
      wins += g > 1.5 * gi && g > 1.5 * go;
    }
  }
  ASSERT_GE(tops, 6);
  std::printf("tops %d: mean Sobel along GT %.1f, GT x0.8 %.1f, GT x1.2 %.1f; GT > 1.5x both in %d\n", tops,
              sum_gt / tops, sum_in / tops, sum_out / tops, wins);
  EXPECT_GT(sum_gt, 2.5 * sum_in);
  EXPECT_GT(sum_gt, 2.5 * sum_out);
  EXPECT_GE(wins, static_cast<int>(0.9 * tops));
}

TEST(SceneGenerator, Deterministic) {
  const sc::Scene a = sc::RenderScene(12345), b = sc::RenderScene(12345), c = sc::RenderScene(12346);
  ASSERT_FALSE(a.gray.empty());
  EXPECT_EQ(cv::norm(a.gray, b.gray, cv::NORM_INF), 0);
  ASSERT_EQ(a.truth.size(), b.truth.size());
  for (std::size_t i = 0; i < a.truth.size(); ++i) EXPECT_EQ(sc::FormatTruthLine(a.truth[i]), sc::FormatTruthLine(b.truth[i]));
  EXPECT_GT(cv::norm(a.gray, c.gray, cv::NORM_L1), 0);
}

TEST(SceneGenerator, DatasetFilesRoundTrip) {
  const fs::path dir = TempDir("dataset");
  ASSERT_TRUE(sc::WriteSceneDataset(dir.string(), 3, 7).ok());
  for (int i = 0; i < 3; ++i) {
    char stem[32];
    std::snprintf(stem, sizeof stem, "scene_%04d", i);
    const sc::Scene s = sc::RenderScene(sc::MixSeed(7, static_cast<std::uint64_t>(i)));
    const cv::Mat img = cv::imread((dir / "images" / (std::string(stem) + ".png")).string(), cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(img.empty());
    ASSERT_EQ(img.type(), CV_8UC1);
    EXPECT_EQ(cv::norm(img, s.gray, cv::NORM_INF), 0);
    std::ifstream in(dir / "gt" / (std::string(stem) + ".txt"));
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    ASSERT_EQ(lines.size(), s.truth.size());
    for (std::size_t k = 0; k < lines.size(); ++k) {
      EXPECT_EQ(lines[k], sc::FormatTruthLine(s.truth[k]));
      double cx, cy, a, b, th;
      ASSERT_EQ(std::sscanf(lines[k].c_str(), "%lf %lf %lf %lf %lf", &cx, &cy, &a, &b, &th), 5);
      EXPECT_NEAR(cx, s.truth[k].cx, 1e-4);
      EXPECT_NEAR(a, s.truth[k].a, 1e-4);
      EXPECT_NEAR(th, s.truth[k].theta, 1e-6);
    }
  }
  // No temporary files are left.
  for (const auto& e : fs::recursive_directory_iterator(dir)) EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos);
  fs::remove_all(dir);
}

TEST(SceneGenerator, BadArguments) {
  sc::SceneOptions o;
  o.width = 8;
  EXPECT_FALSE(sc::ValidateSceneOptions(o).ok());
  EXPECT_TRUE(sc::RenderScene(1, o).gray.empty());
  o = {};
  o.min_tilt_deg = 0;
  EXPECT_FALSE(sc::ValidateSceneOptions(o).ok());
  o = {};
  o.min_objects = 4;
  o.max_objects = 2;
  EXPECT_FALSE(sc::ValidateSceneOptions(o).ok());
  o = {};
  o.noise_sigma = NAN;
  EXPECT_FALSE(sc::ValidateSceneOptions(o).ok());
  EXPECT_TRUE(sc::ValidateSceneOptions(sc::SceneOptions{}).ok());
  EXPECT_FALSE(sc::WriteSceneDataset("", 1, 1).ok());
  const fs::path dir = TempDir("bad");
  EXPECT_FALSE(sc::WriteSceneDataset(dir.string(), -1, 1).ok());
  o = {};
  o.height = 100000;
  const ellipsekit::Status st = sc::WriteSceneDataset(dir.string(), 1, 1, o);
  EXPECT_FALSE(st.ok());
  EXPECT_NE(st.message().find("size"), std::string::npos) << st.message();

  sc::ConveyorSceneOptions co;
  co.speed_m_s = 0;
  EXPECT_FALSE(sc::ValidateConveyorOptions(co).ok());
  co = {};
  co.frames = 0;
  EXPECT_FALSE(sc::WriteConveyorSequence(dir.string(), 1, co).ok());
  co = {};
  co.depth_invalid_fraction = 2;
  EXPECT_FALSE(sc::ValidateConveyorOptions(co).ok());
  EXPECT_TRUE(sc::ValidateConveyorOptions(sc::ConveyorSceneOptions{}).ok());
  fs::remove_all(dir);
}

// --------------------------------------------------------------- conveyor sequences
TEST(ConveyorScene, TriangleWaveMotion) {
  sc::ConveyorSequence s;
  s.start_point = cv::Vec3d(0, 0, 0.1);
  s.end_point = cv::Vec3d(0.3, 0.4, 0.1);  // length 0.5
  s.length_m = 0.5;
  s.speed_m_s = 0.1;
  EXPECT_NEAR(s.PositionAt(0), 0, 1e-12);
  EXPECT_NEAR(s.PositionAt(2), 0.2, 1e-12);
  EXPECT_NEAR(s.PositionAt(5), 0.5, 1e-12);
  EXPECT_NEAR(s.PositionAt(6), 0.4, 1e-12);  // return phase
  EXPECT_NEAR(s.PositionAt(11), 0.1, 1e-12);
  const cv::Vec3d p = s.TopCentreAt(6);
  EXPECT_NEAR(p[0], 0.24, 1e-12);
  EXPECT_NEAR(p[1], 0.32, 1e-12);
  EXPECT_NEAR(p[2], 0.1, 1e-12);
}

// exposure_s: the images average the motion over the shutter time (blur along the guide), the
// truth and the depth stay those of mid-exposure; out-of-range values are rejected.
TEST(ConveyorScene, ExposureBlursTheImageOnly) {
  sc::ConveyorSceneOptions co;
  co.width = 320;
  co.height = 240;
  co.frames = 4;
  co.speed_m_s = 2;  // ~20 px per frame at this size
  co.noise_sigma = 0;  // so that the gradient energy below is the scene's alone
  auto render = [&](double exposure) {
    co.exposure_s = exposure;
    std::vector<sc::ConveyorFrame> frames;
    EXPECT_TRUE(sc::RenderConveyorSequence(5, co, nullptr, [&](const sc::ConveyorFrame& f) {
                  frames.push_back(f);
                  return ellipsekit::Status::Ok();
                }).ok());
    return frames;
  };
  const std::vector<sc::ConveyorFrame> still = render(0), blurred = render(1 / co.fps);
  ASSERT_EQ(still.size(), 4u);
  ASSERT_EQ(blurred.size(), 4u);
  // Edge energy along the motion (the sum of squared directional derivatives, which a blur
  // along that direction lowers) around the top: the blurred image has clearly less.
  auto energy = [](const cv::Mat& gray, const Ellipse& e, cv::Vec2d motion) {
    const int r = static_cast<int>(e.a) + 30;
    const cv::Rect box = cv::Rect(static_cast<int>(e.cx) - r, static_cast<int>(e.cy) - r, 2 * r, 2 * r) &
                         cv::Rect(0, 0, gray.cols, gray.rows);
    cv::Mat gx, gy;
    cv::Sobel(gray(box), gx, CV_32F, 1, 0);
    cv::Sobel(gray(box), gy, CV_32F, 0, 1);
    motion /= cv::norm(motion);
    const cv::Mat along = gx * motion[0] + gy * motion[1];
    return along.dot(along);
  };
  for (std::size_t i = 1; i < still.size(); ++i) {  // frame 0 starts at rest (t - exposure / 2 < 0)
    EXPECT_LT(cv::norm(still[i].top_centre - blurred[i].top_centre), 1e-12);
    EXPECT_EQ(still[i].truth.cx, blurred[i].truth.cx);
    EXPECT_EQ(still[i].truth.a, blurred[i].truth.a);
    EXPECT_EQ(cv::norm(still[i].depth_mm, blurred[i].depth_mm, cv::NORM_INF), 0);
    const cv::Vec2d motion = still[i].top_pixel - still[i - 1].top_pixel;
    const double e_still = energy(still[i].gray, still[i].truth, motion);
    const double e_blurred = energy(blurred[i].gray, blurred[i].truth, motion);
    EXPECT_GT(cv::norm(motion), 10);
    EXPECT_LT(e_blurred, 0.5 * e_still) << "frame " << i << ": " << e_still << " -> " << e_blurred;
  }
  co = {};
  co.exposure_s = -0.001;
  EXPECT_FALSE(sc::ValidateConveyorOptions(co).ok());
  co.exposure_s = 1.5 / co.fps;
  EXPECT_FALSE(sc::ValidateConveyorOptions(co).ok());
  co.exposure_s = 1 / co.fps;
  EXPECT_TRUE(sc::ValidateConveyorOptions(co).ok());
}

TEST(ConveyorScene, FramesHaveExactTruthAndDepth) {
  sc::ConveyorSceneOptions co;
  co.width = 320;
  co.height = 240;
  co.frames = 8;
  co.speed_m_s = 0.1;
  sc::ConveyorSequence info;
  std::vector<sc::ConveyorFrame> frames;
  ASSERT_TRUE(sc::RenderConveyorSequence(3, co, &info, [&](const sc::ConveyorFrame& f) {
                frames.push_back(f);
                return ellipsekit::Status::Ok();
              }).ok());
  ASSERT_EQ(frames.size(), 8u);
  const cv::Matx33d R(info.T_world_camera(0, 0), info.T_world_camera(0, 1), info.T_world_camera(0, 2),
                      info.T_world_camera(1, 0), info.T_world_camera(1, 1), info.T_world_camera(1, 2),
                      info.T_world_camera(2, 0), info.T_world_camera(2, 1), info.T_world_camera(2, 2));
  const cv::Vec3d pos(info.T_world_camera(0, 3), info.T_world_camera(1, 3), info.T_world_camera(2, 3));
  EXPECT_LT(cv::norm(R.t() * R - cv::Matx33d::eye()), 1e-9);
  for (const sc::ConveyorFrame& f : frames) {
    EXPECT_NEAR(f.t, f.index / co.fps, 1e-12);
    const cv::Vec3d truth = info.TopCentreAt(f.t);
    EXPECT_LT(cv::norm(truth - f.top_centre), 1e-12);
    // Camera frame: project with K, and the depth image at that pixel is the top's z (noise <= ~5 mm).
    const cv::Vec3d pc = R.t() * (f.top_centre - pos);
    ASSERT_GT(pc[2], 0);
    const cv::Vec3d uvw = info.K * pc;
    EXPECT_NEAR(uvw[0] / uvw[2], f.top_pixel[0], 1e-6);
    EXPECT_NEAR(uvw[1] / uvw[2], f.top_pixel[1], 1e-6);
    // The true ellipse centre is near (not at: perspective) the projected centre.
    EXPECT_LT(std::hypot(f.truth.cx - f.top_pixel[0], f.truth.cy - f.top_pixel[1]), 0.2 * f.truth.a);
    ASSERT_EQ(f.depth_mm.type(), CV_16UC1);
    std::vector<double> zs;
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        const int v = f.depth_mm.at<std::uint16_t>(static_cast<int>(std::lround(f.top_pixel[1])) + dy,
                                                   static_cast<int>(std::lround(f.top_pixel[0])) + dx);
        if (v > 0) zs.push_back(v * 0.001);
      }
    ASSERT_GE(zs.size(), 15u);
    std::nth_element(zs.begin(), zs.begin() + zs.size() / 2, zs.end());
    EXPECT_NEAR(zs[zs.size() / 2], pc[2], 0.003);
  }
  // Deterministic.
  std::vector<sc::ConveyorFrame> again;
  ASSERT_TRUE(sc::RenderConveyorSequence(3, co, nullptr, [&](const sc::ConveyorFrame& f) {
                again.push_back(f);
                return ellipsekit::Status::Ok();
              }).ok());
  ASSERT_EQ(again.size(), frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(cv::norm(again[i].gray, frames[i].gray, cv::NORM_INF), 0);
    EXPECT_EQ(cv::norm(again[i].depth_mm, frames[i].depth_mm, cv::NORM_INF), 0);
  }
}

}  // namespace
