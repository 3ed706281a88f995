#include "tools/cli/pr_plot.h"

#include <cstdio>

#include <opencv2/imgproc.hpp>

#include "tools/cli/image_io.h"
#include "tools/eval/ellipse_io.h"

namespace ellipsekit::cli {

namespace {

constexpr int kWidth = 640, kHeight = 480, kLeft = 70, kRight = 20, kTop = 50, kBottom = 60;

cv::Point ToPixel(double recall, double precision) {
  const double x = kLeft + recall * (kWidth - kLeft - kRight);
  const double y = kHeight - kBottom - precision * (kHeight - kTop - kBottom);
  return {static_cast<int>(x + 0.5), static_cast<int>(y + 0.5)};
}

void Text(cv::Mat* img, const std::string& s, cv::Point at, double size = 0.45) {
  cv::putText(*img, s, at, cv::FONT_HERSHEY_SIMPLEX, size, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
}

}  // namespace

bool WritePrCurve(const eval::PrCurve& curve, const std::string& title, const std::string& png,
                  const std::string& csv, std::string* error) {
  cv::Mat img(kHeight, kWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  for (int i = 0; i <= 5; ++i) {
    const double v = i / 5.0;
    cv::line(img, ToPixel(v, 0), ToPixel(v, 1), cv::Scalar(225, 225, 225), 1);
    cv::line(img, ToPixel(0, v), ToPixel(1, v), cv::Scalar(225, 225, 225), 1);
    char label[8];
    std::snprintf(label, sizeof label, "%.1f", v);
    Text(&img, label, ToPixel(v, 0) + cv::Point(-10, 20));
    Text(&img, label, ToPixel(0, v) + cv::Point(-35, 5));
  }
  cv::rectangle(img, ToPixel(0, 1), ToPixel(1, 0), cv::Scalar(0, 0, 0), 1);
  Text(&img, "recall", ToPixel(0.5, 0) + cv::Point(-25, 45), 0.5);
  Text(&img, "precision", {5, kTop - 10}, 0.5);
  char heading[160];
  std::snprintf(heading, sizeof heading, "%s  AP %.3f", title.c_str(), curve.average_precision);
  Text(&img, heading, {kLeft, 25}, 0.5);
  // The curve as steps: each point's precision from the previous recall to its own.
  cv::Point previous = curve.points.empty() ? ToPixel(0, 1) : ToPixel(0, curve.points.front().precision);
  for (const eval::PrPoint& p : curve.points) {
    const cv::Point here = ToPixel(p.recall, p.precision);
    cv::line(img, previous, {here.x, previous.y}, cv::Scalar(200, 80, 0), 2, cv::LINE_AA);
    cv::line(img, {here.x, previous.y}, here, cv::Scalar(200, 80, 0), 2, cv::LINE_AA);
    previous = here;
  }
  if (!curve.points.empty()) {
    const eval::PrPoint& all = curve.points.back();
    cv::circle(img, ToPixel(all.recall, all.precision), 5, cv::Scalar(0, 0, 220), 2, cv::LINE_AA);
  }
  std::string text = "threshold,precision,recall\n";
  for (const eval::PrPoint& p : curve.points) {
    char line[96];
    std::snprintf(line, sizeof line, "%.6f,%.6f,%.6f\n", p.threshold, p.precision, p.recall);
    text += line;
  }
  if (Status st = eval::WriteFileAtomically(csv, text); !st.ok()) {
    *error = st.message();
    return false;
  }
  return WriteImageAtomically(png, img, error);
}

}  // namespace ellipsekit::cli
