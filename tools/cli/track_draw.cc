// Drawing of tracks and the grasp target (see track_draw.h).
#include "tools/cli/track_draw.h"

#include <cstdio>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "tools/cli/draw.h"

namespace ellipsekit::cli {

namespace {

cv::Scalar IdColour(std::int64_t id) {
  static const cv::Scalar kPalette[] = {{0, 200, 0},   {255, 160, 0}, {0, 200, 255}, {255, 0, 200},
                                        {0, 255, 160}, {160, 80, 255}, {255, 255, 0}, {80, 160, 255}};
  return kPalette[static_cast<std::size_t>(id) % (sizeof kPalette / sizeof kPalette[0])];
}

}  // namespace

void TrackDrawer::Draw(const cv::Mat& gray, const robot::FrameLoop& loop, const robot::FrameOutput& out,
                       cv::Mat* bgr) {
  cv::cvtColor(gray, *bgr, cv::COLOR_GRAY2BGR);
  // Trails: forget tracks that are gone, append this frame's centres.
  for (auto it = trails_.begin(); it != trails_.end();) {
    bool live = false;
    for (const robot::TrackOutput& t : out.tracks) live |= t.id == it->first;
    it = live ? std::next(it) : trails_.erase(it);
  }
  Eigen::Vector2d riding(0, 0);
  bool has_riding = false;
  for (const robot::TrackOutput& t : out.tracks) {
    const cv::Point2d c = t.source != robot::CentreSource::kNone ? cv::Point2d(t.centre_pixel.x(), t.centre_pixel.y())
                                                                 : cv::Point2d(t.ellipse.cx, t.ellipse.cy);
    auto& trail = trails_[t.id];
    trail.push_back(c);
    while (static_cast<int>(trail.size()) > trail_length_) trail.pop_front();
    const bool confirmed = t.state == robot::TrackState::kConfirmed;
    const cv::Scalar col = t.state == robot::TrackState::kLost ? cv::Scalar(150, 150, 150) : IdColour(t.id);
    for (std::size_t i = 1; i < trail.size(); ++i)
      cv::line(*bgr, trail[i - 1], trail[i], col, 1, cv::LINE_AA);
    DrawEllipse(bgr, t.ellipse, col, confirmed ? 2 : 1);
    cv::drawMarker(*bgr, c, col, cv::MARKER_CROSS, 7, 1, cv::LINE_AA);
    std::string label(1, '#');  // (appends: GCC 12 warns falsely on "literal" + string)
    label += std::to_string(t.id);
    label += ' ';
    label += robot::TrackStateName(t.state);
    if (t.on_conveyor) label += " belt";
    const cv::Point org(static_cast<int>(t.ellipse.cx - t.ellipse.a), static_cast<int>(t.ellipse.cy - t.ellipse.a - 6));
    cv::putText(*bgr, label, org, cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
    cv::putText(*bgr, label, org, cv::FONT_HERSHEY_SIMPLEX, 0.45, col, 1, cv::LINE_AA);
    if (t.on_conveyor) {
      riding = t.centre_pixel;
      has_riding = true;
    }
  }
  char caption[160];
  std::snprintf(caption, sizeof caption, "t %.3f s  %zu track(s)  grasp: %s", out.stamp_s, out.tracks.size(),
                out.grasp.valid ? "yes" : (out.grasp.track_id >= 0 ? "wait for return" : "none"));
  if (out.grasp.track_id >= 0) {
    auto px = loop.ProjectWorld(out.grasp.target);
    if (px.ok()) {
      const cv::Point2d g(px.value.x(), px.value.y());
      const cv::Scalar red = out.grasp.valid ? kRed : cv::Scalar(0, 120, 255);
      if (has_riding) cv::line(*bgr, cv::Point2d(riding.x(), riding.y()), g, red, 1, cv::LINE_AA);
      cv::circle(*bgr, g, 6, red, 1, cv::LINE_AA);
      cv::drawMarker(*bgr, g, red, cv::MARKER_CROSS, 12, 2, cv::LINE_AA);
      char lbl[48];
      std::snprintf(lbl, sizeof lbl, "target t+%.2fs", out.grasp.target_time_s - out.stamp_s);
      cv::putText(*bgr, lbl, g + cv::Point2d(8, 14), cv::FONT_HERSHEY_SIMPLEX, 0.4, red, 1, cv::LINE_AA);
    }
  }
  DrawCaption(bgr, caption);
}

}  // namespace ellipsekit::cli
