// Writes the inputs of the cli_error_* tests into DIR (created at test time, never committed):
//   good.png            a 96x96 8-bit gray image with one ellipse (the file that must still be processed)
//   empty.png           0 bytes
//   text.png            a text file named like an image
//   truncated.png       the first half of a valid PNG
//   corrupt.png         a valid PNG with its image data overwritten by garbage
//   truncated.jpg       the first half of a valid JPEG
//   corrupt.jpg         a valid JPEG with its entropy-coded data overwritten by garbage
//   gray16.png          16-bit gray (must be converted, with a note)
//   colour.png          8-bit BGR (must be converted, with a note)
//   one_pixel.png       1x1 (too small: refused)
//   wide_65536.png      65536x1 (larger than the detector's 16384 px side limit)
//   a_directory.png/    a directory
//   ggg...g.png         good.png under a 248-character stem (see below)
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace fs = std::filesystem;

namespace {

std::vector<unsigned char> Encode(const std::string& ext, const cv::Mat& m) {
  std::vector<unsigned char> buf;
  if (!cv::imencode(ext, m, buf)) {
    std::fprintf(stderr, "make_files: cannot encode %s\n", ext.c_str());
    std::exit(1);
  }
  return buf;
}

void Write(const fs::path& p, const std::vector<unsigned char>& bytes) {
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!f) {
    std::fprintf(stderr, "make_files: cannot write %s\n", p.string().c_str());
    std::exit(1);
  }
}

std::vector<unsigned char> FirstHalf(std::vector<unsigned char> b) {
  b.resize(b.size() / 2);
  return b;
}

// Overwrites bytes [from, to) with a fixed pseudo-random pattern.
std::vector<unsigned char> Garble(std::vector<unsigned char> b, std::size_t from, std::size_t to) {
  unsigned x = 12345;
  for (std::size_t i = from; i < to && i < b.size(); ++i) {
    x = x * 1103515245u + 12345u;
    b[i] = static_cast<unsigned char>(x >> 16);
  }
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: cli_errors_make_files DIR\n");
    return 2;
  }
  const fs::path dir(argv[1]);
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir / "a_directory.png");

  cv::Mat good(96, 96, CV_8UC1, cv::Scalar(40));
  cv::ellipse(good, cv::Point(46, 50), cv::Size(30, 20), 25, 0, 360, cv::Scalar(210), cv::FILLED);
  // Texture so that a JPEG has plenty of entropy-coded data to damage.
  cv::Mat textured = good.clone();
  for (int y = 0; y < textured.rows; ++y)
    for (int x = 0; x < textured.cols; ++x) textured.at<unsigned char>(y, x) += static_cast<unsigned char>((x * 7 + y * 13) % 23);
  Write(dir / "good.png", Encode(".png", good));
  // good.png again under a 248-character stem: --draw's output name (stem + ".png", 252 characters)
  // is legal, its temporary ("." + stem + ".tmp<pid>.png", at least 258) is over the 255-byte name
  // limit, so writing the temporary fails (cli_error_draw_write_fails).
  Write(dir / (std::string(248, 'g') + ".png"), Encode(".png", good));
  Write(dir / "empty.png", {});
  const std::string text = "this is not an image\n";
  Write(dir / "text.png", std::vector<unsigned char>(text.begin(), text.end()));

  const std::vector<unsigned char> png = Encode(".png", textured);
  Write(dir / "truncated.png", FirstHalf(png));
  // PNG layout: 8-byte signature, IHDR chunk (25 bytes), then IDAT; damage the IDAT payload.
  Write(dir / "corrupt.png", Garble(png, 33 + 8 + 16, png.size() - 12));

  const std::vector<unsigned char> jpg = Encode(".jpg", textured);
  Write(dir / "truncated.jpg", FirstHalf(jpg));
  // Damage the second half of the file, which is entropy-coded scan data (the headers come first).
  Write(dir / "corrupt.jpg", Garble(jpg, jpg.size() / 2, jpg.size() - 2));

  cv::Mat g16;
  good.convertTo(g16, CV_16U, 257.0);
  Write(dir / "gray16.png", Encode(".png", g16));
  cv::Mat colour;
  cv::cvtColor(good, colour, cv::COLOR_GRAY2BGR);
  colour.setTo(cv::Scalar(0, 0, 255), good > 100);
  Write(dir / "colour.png", Encode(".png", colour));
  Write(dir / "one_pixel.png", Encode(".png", cv::Mat(1, 1, CV_8UC1, cv::Scalar(128))));
  cv::Mat wide(1, 65536, CV_8UC1);
  for (int x = 0; x < wide.cols; ++x) wide.at<unsigned char>(0, x) = static_cast<unsigned char>(x * 31);
  Write(dir / "wide_65536.png", Encode(".png", wide));

  // Unreadable: a copy of good.png with no permissions (root can still read it; the test skips then).
  Write(dir / "unreadable.png", Encode(".png", good));
  fs::permissions(dir / "unreadable.png", fs::perms::none, ec);
  std::printf("cli_errors_make_files: wrote %s\n", dir.string().c_str());
  return 0;
}
