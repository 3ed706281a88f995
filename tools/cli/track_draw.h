// `ellipsekit track --draw DIR / --video FILE`: one frame of the robot loop drawn for a person.
// Each track: its ellipse (colour per id; thick when confirmed, thin when tentative, grey when
// lost), "#id state", a trail of its past top-centre pixels; the grasp target predicted for
// now + latency, projected into the image (red cross in a circle) with a line from the riding
// track; a caption with the time, the track count and the grasp decision.
#pragma once

#include <cstdint>
#include <deque>
#include <map>

#include <opencv2/core.hpp>

#include "ellipsekit/robot/frame_loop.h"

namespace ellipsekit::cli {

class TrackDrawer {
 public:
  explicit TrackDrawer(int trail_length = 45) : trail_length_(trail_length) {}
  // Draws `out` (from `loop`, which projects the grasp target) over the gray frame into *bgr.
  void Draw(const cv::Mat& gray, const robot::FrameLoop& loop, const robot::FrameOutput& out, cv::Mat* bgr);

 private:
  int trail_length_;
  std::map<std::int64_t, std::deque<cv::Point2d>> trails_;
};

}  // namespace ellipsekit::cli
