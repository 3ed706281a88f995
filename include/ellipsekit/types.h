// ellipsekit public types: image view, ellipse, status.
//
// Conventions (DESIGN.md): pixel centres at integer coordinates, x right, y down.
// An ellipse is (cx, cy, a, b, theta): semi-axes a >= b in pixels, the major axis along
// (cos theta, sin theta) in image coordinates — OpenCV's RotatedRect angle, in radians,
// normalised to [-pi/2, pi/2).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>

namespace ellipsekit {

// A borrowed 8-bit single-channel image; ellipsekit never copies or frees it.
// stride is the distance in bytes between the starts of two rows (>= width).
struct ImageView {
  const std::uint8_t* data = nullptr;
  int width = 0;
  int height = 0;
  std::ptrdiff_t stride = 0;
};

struct Ellipse {
  double cx = 0, cy = 0;  // centre, px
  double a = 0, b = 0;    // semi-axes, px, a >= b
  double theta = 0;       // major-axis angle, rad, in [-pi/2, pi/2)
  // A detection's support, in [0, 1]: the share of 64 points spread along the outline that have an
  // edge pixel within 1 px whose gradient lies along the outline's normal (on the edge map of the
  // level it was found on). 1: edges back the whole outline; 0.5: half of it (hidden, or cut by
  // the frame). Rank or threshold detections by it (`ellipsekit eval --curve`). While a candidate
  // inside the detector it is the paper's K(tau) + psi(tau) (eqs. 13, 16), which orders clustering.
  double score = 0;
};

enum class StatusCode {
  kOk = 0,
  kInvalidArgument,  // bad image view or options
  kUnavailable,      // a backend that cannot run here (no Vulkan device, SIMD not built)
  kInternal,
};

// The outcome of a call: ok, or a code with a message naming the problem.
class Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}
  static Status Ok() { return {}; }
  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  const std::string& message() const { return message_; }

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

}  // namespace ellipsekit
