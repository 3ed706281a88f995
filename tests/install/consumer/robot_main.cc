// Uses the installed robot adapter (ellipsekit::robot / pkg-config ellipsekit-robot): the 3-D rim
// centre of a disc 0.6 m in front of the camera from a synthetic depth image, and one FrameLoop call.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include <ellipsekit/robot/robot.h>

int main() {
  namespace er = ellipsekit::robot;
  const int w = 160, h = 120;
  const er::CameraModel cam = er::CameraModel::FromIntrinsics(200, 200, 79.5, 59.5, {}, w, h);
  // A fronto-parallel disc of radius 5 cm at z = 0.6 m on a background at 0.9 m.
  std::vector<std::uint16_t> depth(static_cast<std::size_t>(w) * h);
  const double r_px = 200 * 0.05 / 0.6;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      depth[static_cast<std::size_t>(y) * w + x] = std::hypot(x - 79.5, y - 59.5) <= r_px ? 600 : 900;
  er::DepthImageView dv{depth.data(), w, h, static_cast<std::size_t>(w) * 2, er::DepthEncoding::k16UC1};
  er::RimCentreSampler rim;
  rim.mutable_options().plane_normal = Eigen::Vector3d(0, 0, -1);
  auto s = rim.Sample(ellipsekit::Ellipse{79.5, 59.5, r_px, r_px, 0, 0}, dv, cam);
  if (!s.ok() || std::abs(s.value.centre.z() - 0.6) > 0.002 || s.value.centre.head<2>().norm() > 0.002) {
    std::fprintf(stderr, "robot consumer: rim centre wrong: %s\n", s.status.message().c_str());
    return 1;
  }
  er::FrameLoop loop(cam, er::FrameLoopOptions{});
  std::vector<std::uint8_t> gray(static_cast<std::size_t>(w) * h, 128);
  er::FrameOutput out;
  const ellipsekit::Status st = loop.ProcessFrame(ellipsekit::ImageView{gray.data(), w, h, w}, &dv, 0.0, &out);
  if (!loop.status().ok() || !st.ok()) {
    std::fprintf(stderr, "robot consumer: frame loop failed: %s\n", st.message().c_str());
    return 1;
  }
  std::printf("robot consumer: rim centre z %.4f m from %d samples, %zu tracks\n", s.value.centre.z(),
              s.value.inliers, out.tracks.size());
  return 0;
}
