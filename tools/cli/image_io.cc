#include "tools/cli/image_io.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>
#include <system_error>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "kernels/arc_types.h"  // kMaxImageDimension

namespace ellipsekit::cli {
namespace fs = std::filesystem;

namespace {

void AddNote(LoadedImage* out, const std::string& note) {
  if (!out->note.empty()) out->note += "; ";
  out->note += note;
}

// Decodes `bytes` with cv::imdecode while fd 2 is redirected to a temporary file: libpng,
// libjpeg and OpenCV's own logger print straight to stderr, and the CLI's contract is one line
// per problem. What they printed is returned in `chatter` (trimmed lines, "; "-joined).
cv::Mat DecodeQuietly(const std::vector<unsigned char>& bytes, std::string* chatter) {
  std::fflush(stderr);
  std::FILE* sink = std::tmpfile();
  const int saved = sink != nullptr ? ::dup(2) : -1;
  if (saved >= 0) ::dup2(::fileno(sink), 2);
  cv::Mat raw;
  try {
    raw = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    raw.release();
    chatter->append(e.what());
  }
  if (saved >= 0) {
    std::fflush(stderr);
    ::dup2(saved, 2);
    ::close(saved);
    std::rewind(sink);
    char line[512];
    while (std::fgets(line, sizeof line, sink) != nullptr) {
      std::string text(line);
      while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
      if (text.empty()) continue;
      if (!chatter->empty()) chatter->append("; ");
      chatter->append(text);
    }
  }
  if (sink != nullptr) std::fclose(sink);
  return raw;
}

// libjpeg reports damaged or cut-off scan data as warnings and still returns an image (the
// missing part filled in); such an image must not be detected on as if it were the real frame.
bool IsDamageWarning(const std::string& chatter) {
  return chatter.find("Corrupt JPEG data") != std::string::npos ||
         chatter.find("Premature end") != std::string::npos ||
         chatter.find("libpng error") != std::string::npos;
}

// A JPEG whose last scan (the bytes after its last SOS marker, FF DA) has no end-of-image marker
// (FF D9) was cut off. libjpeg decodes such a file without a word and pads the missing rows, so
// the check is made here. (Inside scan data a 0xFF byte is always followed by 0x00 or a restart
// marker, so FF D9 there is the real end.)
bool IsTruncatedJpeg(const std::vector<unsigned char>& b) {
  if (b.size() < 4 || b[0] != 0xFF || b[1] != 0xD8) return false;  // not a JPEG
  std::size_t last_sos = 0;
  for (std::size_t i = 0; i + 1 < b.size(); ++i)
    if (b[i] == 0xFF && b[i + 1] == 0xDA) last_sos = i;
  if (last_sos == 0) return false;  // no scan at all: the decoder refuses it
  for (std::size_t i = last_sos + 2; i + 1 < b.size(); ++i)
    if (b[i] == 0xFF && b[i + 1] == 0xD9) return false;
  return true;
}

}  // namespace

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
  std::ifstream file(path, std::ios::binary);
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (file.bad()) {
    *error = "cannot read (I/O error)";
    return false;
  }
  if (bytes.empty()) {
    *error = "empty file (0 bytes)";
    return false;
  }
  std::string chatter;
  const cv::Mat raw = DecodeQuietly(bytes, &chatter);
  if (raw.empty()) {
    *error = "not a readable image (OpenCV could not decode it)";
    if (!chatter.empty()) *error += ": " + chatter;
    return false;
  }
  if (IsTruncatedJpeg(bytes)) {
    *error = "truncated JPEG (no end-of-image marker after the last scan)";
    return false;
  }
  if (IsDamageWarning(chatter)) {
    *error = "corrupt or truncated image: " + chatter;
    return false;
  }
  if (!chatter.empty()) out->note = "decoder: " + chatter;

  cv::Mat depth8;
  switch (raw.depth()) {
    case CV_8U:
      depth8 = raw;
      break;
    case CV_16U:
      raw.convertTo(depth8, CV_8U, 1.0 / 257.0);
      AddNote(out, "16-bit image scaled to 8-bit (value / 257)");
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
      AddNote(out, "colour image converted to gray (0.299 R + 0.587 G + 0.114 B)");
      break;
    case 4:
      cv::cvtColor(depth8, out->color, cv::COLOR_BGRA2BGR);
      cv::cvtColor(depth8, out->gray, cv::COLOR_BGRA2GRAY);
      AddNote(out, "colour image converted to gray (0.299 R + 0.587 G + 0.114 B), alpha dropped");
      break;
    default:
      *error = "unsupported number of channels (" + std::to_string(depth8.channels()) + ")";
      return false;
  }
  // Sobel's 3x3 window needs an interior pixel: a frame with a side under 3 px has only border
  // gradients, so no edge and no ellipse can come out of it. The library accepts such frames (and
  // finds nothing); the CLI tells the user instead of printing an empty result. A frame over the
  // side limit (65536x1, say) is left to detect(), whose error names that limit.
  const bool within_limit = std::max(out->gray.cols, out->gray.rows) <= kMaxImageDimension;
  if (within_limit && (out->gray.cols < 3 || out->gray.rows < 3)) {
    *error = "image is " + std::to_string(out->gray.cols) + "x" + std::to_string(out->gray.rows) +
             ": too small to hold an ellipse (both sides must be at least 3 px)";
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
