// Image loading for detection and atomic image writing.
#pragma once

#include <string>

#include <opencv2/core.hpp>

#include "ellipsekit/types.h"

namespace ellipsekit::cli {

struct LoadedImage {
  cv::Mat gray;   // CV_8UC1, what detect() sees
  cv::Mat color;  // CV_8UC3 BGR, for drawing overlays
  std::string note;  // a conversion worth telling the user about (e.g. 16-bit scaled to 8), or ""
};

// Loads any png / jpg / bmp / ... OpenCV reads. Colour is converted to gray (BGR weights of
// cv::cvtColor), alpha is dropped, 16-bit is scaled to 8-bit (value / 257); each conversion
// is told in `note`. Damaged files (decoder warnings about corrupt or truncated data) are errors,
// not images: the decoder would fill the missing part in.
// On failure returns false and sets `error` to the problem ("no such file", "not a readable
// image", ...), without the path.
bool LoadImage(const std::string& path, LoadedImage* out, std::string* error);

// A borrowed view of an 8-bit single-channel Mat.
ImageView ViewOf(const cv::Mat& gray);

// Encodes `image` by `path`'s extension into a temporary file in the same folder, then renames
// it onto `path`. On failure returns false with `error` set.
bool WriteImageAtomically(const std::string& path, const cv::Mat& image, std::string* error);

// Creates `dir` and its parents when missing; false with `error` set on failure.
bool EnsureDirectory(const std::string& dir, std::string* error);

}  // namespace ellipsekit::cli
