#include "tools/cli/draw.h"

#include <cmath>
#include <numbers>
#include <string>

#include <opencv2/imgproc.hpp>

namespace ellipsekit::cli {

void DrawEllipse(cv::Mat* bgr, const Ellipse& e, const cv::Scalar& color, int thickness) {
  if (!std::isfinite(e.cx) || !std::isfinite(e.cy) || !(e.a > 0) || !(e.b > 0) ||
      !std::isfinite(e.a) || !std::isfinite(e.b) || !std::isfinite(e.theta)) {
    return;
  }
  const cv::RotatedRect box(cv::Point2f(static_cast<float>(e.cx), static_cast<float>(e.cy)),
                            cv::Size2f(static_cast<float>(2 * e.a), static_cast<float>(2 * e.b)),
                            static_cast<float>(e.theta * 180.0 / std::numbers::pi));
  cv::ellipse(*bgr, box, color, thickness, cv::LINE_AA);
}

void DrawEllipses(cv::Mat* bgr, const std::vector<Ellipse>& ellipses, const cv::Scalar& color,
                  int thickness) {
  for (const Ellipse& e : ellipses) DrawEllipse(bgr, e, color, thickness);
}

void DrawCentreMark(cv::Mat* bgr, const Ellipse& e, const cv::Scalar& color) {
  if (!std::isfinite(e.cx) || !std::isfinite(e.cy)) return;
  cv::drawMarker(*bgr, cv::Point(static_cast<int>(std::lround(e.cx)), static_cast<int>(std::lround(e.cy))),
                 color, cv::MARKER_CROSS, 10, 2);
}

void DrawCaption(cv::Mat* bgr, const std::string& text) {
  int baseline = 0;
  const double scale = 0.5;
  const cv::Size size = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &baseline);
  cv::rectangle(*bgr, cv::Rect(0, 0, std::min(bgr->cols, size.width + 8), size.height + baseline + 8),
                cv::Scalar(0, 0, 0), cv::FILLED);
  cv::putText(*bgr, text, cv::Point(4, size.height + 4), cv::FONT_HERSHEY_SIMPLEX, scale,
              cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
}

}  // namespace ellipsekit::cli
