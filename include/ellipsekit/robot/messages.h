// Plain structs that mirror the ROS messages the robot adapter reads and writes.
//
// Conventions (REP 103 / 105 / 118):
//   * metres, radians, seconds;
//   * camera optical frame: x right, y down, z forward (along the optical axis);
//   * a pose is a position plus a unit quaternion (x, y, z, w), stamped with a frame id and a time;
//   * depth images: 16-bit unsigned millimetres with 0 = invalid ("16UC1"), or 32-bit float metres
//     with NaN (or +-inf, or <= 0) = invalid ("32FC1").
// No middleware dependency: ros_adapters.h converts to and from real message types by field name.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "ellipsekit/types.h"

namespace ellipsekit::robot {

// builtin_interfaces/Time: seconds and nanoseconds since an epoch chosen by the user.
struct Time {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;

  double seconds() const { return static_cast<double>(sec) + 1e-9 * static_cast<double>(nanosec); }
  static Time FromSeconds(double s) {
    Time t;
    double whole = std::floor(s);
    t.sec = static_cast<std::int32_t>(whole);
    double ns = std::round((s - whole) * 1e9);
    if (ns >= 1e9) {
      ++t.sec;
      ns -= 1e9;
    }
    t.nanosec = static_cast<std::uint32_t>(ns);
    return t;
  }
};

// std_msgs/Header.
struct Header {
  Time stamp;
  std::string frame_id;
};

// geometry_msgs/Point (metres) and Vector3.
struct Point {
  double x = 0, y = 0, z = 0;
};
using Vector3 = Point;

// geometry_msgs/Quaternion; identity by default. (x, y, z, w) order as in ROS.
struct Quaternion {
  double x = 0, y = 0, z = 0, w = 1;
};

// geometry_msgs/Pose and PoseStamped.
struct Pose {
  Point position;
  Quaternion orientation;
};
struct PoseStamped {
  Header header;
  Pose pose;
};

// A point with its 3x3 covariance (row-major, m^2), stamped. ROS has no such message; a user
// publishes it as geometry_msgs/PoseWithCovarianceStamped with the rotation block marked unknown.
struct PointWithCovarianceStamped {
  Header header;
  Point point;
  std::array<double, 9> covariance{};
};

// sensor_msgs/CameraInfo (the fields the adapter uses). K, R row-major 3x3; P row-major 3x4.
// distortion_model "plumb_bob" (D = k1, k2, t1, t2, k3) or "rational_polynomial"
// (D = k1, k2, t1, t2, k3, k4, k5, k6); an empty D means no distortion.
struct CameraInfo {
  Header header;
  std::uint32_t height = 0;
  std::uint32_t width = 0;
  std::string distortion_model = "plumb_bob";
  std::vector<double> d;
  std::array<double, 9> k{};
  std::array<double, 9> r{1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::array<double, 12> p{};
};

enum class DepthEncoding {
  k16UC1,  // uint16 millimetres, 0 = invalid
  k32FC1,  // float metres, NaN / inf / <= 0 = invalid
};

// A borrowed depth image registered to the colour image the ellipses were detected in
// (same size and intrinsics). step is the row pitch in bytes (sensor_msgs/Image.step).
struct DepthImageView {
  const void* data = nullptr;
  int width = 0;
  int height = 0;
  std::size_t step = 0;
  DepthEncoding encoding = DepthEncoding::k16UC1;
};

// An expected-like result: a status, and a value that is meaningful only when status.ok().
template <class T>
struct Result {
  Status status;
  T value{};

  bool ok() const { return status.ok(); }
  static Result Ok(T v) { return Result{Status::Ok(), std::move(v)}; }
  static Result Error(StatusCode code, std::string message) {
    return Result{Status(code, std::move(message)), T{}};
  }
};

}  // namespace ellipsekit::robot
