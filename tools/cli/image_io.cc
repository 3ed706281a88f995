#include "tools/cli/image_io.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <system_error>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace ellipsekit::cli {
namespace fs = std::filesystem;

bool LoadImage(const std::string& path, LoadedImage* out, std::string* error) {
  *out = LoadedImage();
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) {
    *error = "no such file";
    return false;
  }
  if (fs::is_directory(st)) {
    *error = "is a directory, not an image";
    return false;
  }
  if (::access(path.c_str(), R_OK) != 0) {
    *error = "cannot read (permission denied)";
    return false;
  }
  cv::Mat raw;
  try {
    raw = cv::imread(path, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    *error = std::string("cannot decode: ") + e.what();
    return false;
  }
  if (raw.empty()) {
    *error = "not a readable image (OpenCV could not decode it)";
    return false;
  }

  cv::Mat depth8;
  switch (raw.depth()) {
    case CV_8U:
      depth8 = raw;
      break;
    case CV_16U:
      raw.convertTo(depth8, CV_8U, 1.0 / 257.0);
      out->note = "16-bit image scaled to 8-bit (value / 257)";
      break;
    default:
      *error = "unsupported pixel depth (only 8- and 16-bit unsigned images)";
      return false;
  }
  switch (depth8.channels()) {
    case 1:
      out->gray = depth8;
      cv::cvtColor(depth8, out->color, cv::COLOR_GRAY2BGR);
      break;
    case 3:
      out->color = depth8;
      cv::cvtColor(depth8, out->gray, cv::COLOR_BGR2GRAY);
      break;
    case 4:
      cv::cvtColor(depth8, out->color, cv::COLOR_BGRA2BGR);
      cv::cvtColor(depth8, out->gray, cv::COLOR_BGRA2GRAY);
      break;
    default:
      *error = "unsupported number of channels (" + std::to_string(depth8.channels()) + ")";
      return false;
  }
  if (!out->gray.isContinuous()) out->gray = out->gray.clone();
  return true;
}

ImageView ViewOf(const cv::Mat& gray) {
  ImageView view;
  view.data = gray.ptr<std::uint8_t>();
  view.width = gray.cols;
  view.height = gray.rows;
  view.stride = static_cast<std::ptrdiff_t>(gray.step[0]);
  return view;
}

bool WriteImageAtomically(const std::string& path, const cv::Mat& image, std::string* error) {
  const fs::path target(path);
  // Keep the extension last: OpenCV picks the encoder by it.
  std::string tmp_name(1, '.');  // (built by appends: GCC 12 warns falsely on "." + string)
  tmp_name.append(target.stem().string());
  tmp_name.append(".tmp");
  tmp_name.append(std::to_string(static_cast<long>(::getpid())));
  tmp_name.append(target.extension().string());
  const fs::path tmp = target.parent_path() / tmp_name;
  bool ok = false;
  try {
    ok = cv::imwrite(tmp.string(), image);
  } catch (const cv::Exception& e) {
    *error = std::string("cannot encode: ") + e.what();
  }
  if (!ok) {
    if (error->empty()) *error = "cannot write " + tmp.string();
    std::error_code ec;
    fs::remove(tmp, ec);
    return false;
  }
  std::error_code ec;
  fs::rename(tmp, target, ec);
  if (ec) {
    *error = "cannot rename " + tmp.string() + ": " + ec.message();
    fs::remove(tmp, ec);
    return false;
  }
  return true;
}

bool EnsureDirectory(const std::string& dir, std::string* error) {
  std::error_code ec;
  if (fs::is_directory(dir, ec)) return true;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) {
    *error = dir + ": cannot create directory" + (ec ? ": " + ec.message() : "");
    return false;
  }
  return true;
}

}  // namespace ellipsekit::cli
