// Header-only glue between the plain structs of messages.h and real ROS messages, by field name,
// so the adapter needs no middleware: any type with the fields of sensor_msgs/CameraInfo works
// (ROS 2 lower-case k/d/r/p and header.stamp.sec/nanosec, or ROS 1 upper-case K/D/R/P and
// header.stamp.sec/nsec).
//
//   auto info = ellipsekit::robot::CameraInfoFromMsg(*msg);            // sensor_msgs::msg::CameraInfo
//   auto cam  = ellipsekit::robot::CameraModel::FromCameraInfo(info);
//   geometry_msgs::msg::PoseStamped out; ellipsekit::robot::ToPoseMsg(plan.grasp, out);
#pragma once

#include <algorithm>
#include <cstddef>
#include <string>

#include "ellipsekit/robot/messages.h"

namespace ellipsekit::robot {

template <class Stamp>
Time TimeFromMsg(const Stamp& s) {
  Time t;
  t.sec = static_cast<std::int32_t>(s.sec);
  if constexpr (requires { s.nanosec; }) {
    t.nanosec = static_cast<std::uint32_t>(s.nanosec);
  } else if constexpr (requires { s.nsec; }) {
    t.nanosec = static_cast<std::uint32_t>(s.nsec);
  }
  return t;
}

template <class Stamp>
void TimeToMsg(const Time& t, Stamp& s) {
  s.sec = t.sec;
  if constexpr (requires { s.nanosec; }) {
    s.nanosec = t.nanosec;
  } else if constexpr (requires { s.nsec; }) {
    s.nsec = t.nanosec;
  }
}

template <class HeaderMsg>
Header HeaderFromMsg(const HeaderMsg& h) {
  return Header{TimeFromMsg(h.stamp), std::string(h.frame_id)};
}

template <class HeaderMsg>
void HeaderToMsg(const Header& h, HeaderMsg& out) {
  TimeToMsg(h.stamp, out.stamp);
  out.frame_id = h.frame_id;
}

namespace detail {
template <class Src, class Dst>
void CopyN(const Src& src, Dst& dst, std::size_t n) {
  std::size_t i = 0;
  for (auto v : src) {
    if (i >= n) break;
    dst[i++] = static_cast<double>(v);
  }
}
}  // namespace detail

// Any type with CameraInfo's field names.
template <class Msg>
CameraInfo CameraInfoFromMsg(const Msg& m) {
  CameraInfo c;
  c.header = HeaderFromMsg(m.header);
  c.height = static_cast<std::uint32_t>(m.height);
  c.width = static_cast<std::uint32_t>(m.width);
  c.distortion_model = std::string(m.distortion_model);
  if constexpr (requires { m.k; }) {
    c.d.assign(m.d.begin(), m.d.end());
    detail::CopyN(m.k, c.k, 9);
    detail::CopyN(m.r, c.r, 9);
    detail::CopyN(m.p, c.p, 12);
  } else {
    c.d.assign(m.D.begin(), m.D.end());
    detail::CopyN(m.K, c.k, 9);
    detail::CopyN(m.R, c.r, 9);
    detail::CopyN(m.P, c.p, 12);
  }
  return c;
}

// A view of a sensor_msgs/Image holding depth ("16UC1" / "mono16" or "32FC1"); the message must
// outlive the view. Big-endian data is not supported.
template <class ImageMsg>
Result<DepthImageView> DepthViewFromMsg(const ImageMsg& m) {
  DepthImageView v;
  const std::string enc(m.encoding);
  if (enc == "16UC1" || enc == "mono16") {
    v.encoding = DepthEncoding::k16UC1;
  } else if (enc == "32FC1") {
    v.encoding = DepthEncoding::k32FC1;
  } else {
    return Result<DepthImageView>::Error(StatusCode::kInvalidArgument, "depth: unsupported encoding " + enc);
  }
  if (m.is_bigendian) {
    return Result<DepthImageView>::Error(StatusCode::kInvalidArgument, "depth: big-endian data");
  }
  v.data = m.data.data();
  v.width = static_cast<int>(m.width);
  v.height = static_cast<int>(m.height);
  v.step = static_cast<std::size_t>(m.step);
  if (m.data.size() < v.step * static_cast<std::size_t>(v.height)) {
    return Result<DepthImageView>::Error(StatusCode::kInvalidArgument, "depth: data shorter than step * height");
  }
  return Result<DepthImageView>::Ok(v);
}

// Any type with geometry_msgs/PoseStamped's field names.
template <class Msg>
void ToPoseMsg(const PoseStamped& p, Msg& out) {
  HeaderToMsg(p.header, out.header);
  out.pose.position.x = p.pose.position.x;
  out.pose.position.y = p.pose.position.y;
  out.pose.position.z = p.pose.position.z;
  out.pose.orientation.x = p.pose.orientation.x;
  out.pose.orientation.y = p.pose.orientation.y;
  out.pose.orientation.z = p.pose.orientation.z;
  out.pose.orientation.w = p.pose.orientation.w;
}

// Any type with geometry_msgs/PointStamped's field names (the covariance is dropped).
template <class Msg>
void ToPointMsg(const PointWithCovarianceStamped& p, Msg& out) {
  HeaderToMsg(p.header, out.header);
  out.point.x = p.point.x;
  out.point.y = p.point.y;
  out.point.z = p.point.z;
}

}  // namespace ellipsekit::robot
