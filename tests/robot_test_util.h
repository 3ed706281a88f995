// Shared by the robot adapter's tests on rendered frames: views of an OpenCV gray frame and of a
// 16-bit depth image in millimetres (the scene generator's outputs) for the library's calls.
#pragma once

#include <cstddef>
#include <cstdint>

#include <opencv2/core.hpp>

#include "ellipsekit/robot/messages.h"
#include "ellipsekit/types.h"

namespace ellipsekit::test {

inline robot::DepthImageView DepthView(const cv::Mat& depth_mm) {
  robot::DepthImageView dv;
  dv.data = depth_mm.data;
  dv.width = depth_mm.cols;
  dv.height = depth_mm.rows;
  dv.step = depth_mm.step[0];
  dv.encoding = robot::DepthEncoding::k16UC1;
  return dv;
}

inline ImageView View(const cv::Mat& gray) {
  return {gray.ptr<std::uint8_t>(0), gray.cols, gray.rows, static_cast<std::ptrdiff_t>(gray.step[0])};
}

}  // namespace ellipsekit::test
