// Overlay drawing: ellipses on a BGR image, in the project's convention
// cv::ellipse(img, RotatedRect(center, Size(2a, 2b), theta in degrees), ...).
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "ellipsekit/types.h"

namespace ellipsekit::cli {

inline const cv::Scalar kGreen(0, 200, 0);
inline const cv::Scalar kRed(0, 0, 255);
inline const cv::Scalar kYellow(0, 255, 255);

void DrawEllipse(cv::Mat* bgr, const Ellipse& e, const cv::Scalar& color, int thickness);
void DrawEllipses(cv::Mat* bgr, const std::vector<Ellipse>& ellipses, const cv::Scalar& color,
                  int thickness);
// A small cross at the centre, used to mark correct detections.
void DrawCentreMark(cv::Mat* bgr, const Ellipse& e, const cv::Scalar& color);
// One line of text at the top-left corner on a dark band.
void DrawCaption(cv::Mat* bgr, const std::string& text);

}  // namespace ellipsekit::cli
