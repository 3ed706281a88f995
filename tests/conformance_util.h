// The one conformance helper every tests/conformance_<kernel>.cc uses (ncnn's testutil shape):
// a case is a lambda that runs a kernel from a KernelTable into sentinel-filled output planes;
// ExpectAllTargetsMatchScalar runs it once through the scalar reference and once per Highway
// target compiled in and supported here (each target's own table), and compares every byte of every plane,
// padding included, so writes outside the region are caught too.
// Images: ConformanceImages() is the shared input set (tiny sizes, widths 1..70, odd widths,
// padded strides, 640x480 / 1280x720 / 1920x1080 random, flat, noise, every dataset image).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "cpu/simd_kernels.h"
#include "kernels/canny_thresholds.h"
#include "runtime/backend.h"

namespace ellipsekit::conformance {

inline constexpr std::uint8_t kSentinel = 0xA5;

// One output buffer: height rows of `stride` elements, then one guard row; all bytes start as
// kSentinel. Only the width x height region may change.
struct Plane {
  std::string name;
  int width = 0, height = 0, elem_size = 1;
  std::ptrdiff_t stride = 0;  // elements
  std::vector<std::uint8_t> bytes;

  template <class T>
  T* data() { return reinterpret_cast<T*>(bytes.data()); }
};

template <class T>
Plane MakePlane(std::string name, int width, int height, std::ptrdiff_t stride) {
  Plane p;
  p.name = std::move(name);
  p.width = width;
  p.height = height;
  p.elem_size = static_cast<int>(sizeof(T));
  p.stride = stride;
  p.bytes.assign(static_cast<std::size_t>(stride) * (height + 1) * sizeof(T), kSentinel);
  return p;
}

using KernelRun = std::function<std::vector<Plane>(const KernelTable&)>;

inline std::string DescribeMismatch(const Plane& want, const Plane& got, std::size_t byte) {
  const std::size_t elem = byte / want.elem_size;
  const std::ptrdiff_t y = static_cast<std::ptrdiff_t>(elem) / want.stride;
  const std::ptrdiff_t x = static_cast<std::ptrdiff_t>(elem) % want.stride;
  std::ostringstream s;
  s << want.name << " differs at x=" << x << " y=" << y
    << ((x >= want.width || y >= want.height) ? " (OUTSIDE the region)" : "") << ": scalar byte "
    << int(want.bytes[byte]) << ", simd byte " << int(got.bytes[byte]);
  return s.str();
}

// Runs `run` through the scalar table and through the SIMD table once per available target.
inline void ExpectAllTargetsMatchScalar(const std::string& what, const KernelRun& run) {
  const std::vector<Plane> want = run(ScalarKernels());
  // The reference itself must leave the padding alone, or the comparison proves little.
  for (const Plane& p : want) {
    for (std::size_t b = 0; b < p.bytes.size(); ++b) {
      const std::size_t elem = b / p.elem_size;
      const bool inside = static_cast<std::ptrdiff_t>(elem) % p.stride < p.width &&
                          static_cast<std::ptrdiff_t>(elem) / p.stride < p.height;
      if (!inside && p.bytes[b] != kSentinel) {
        ADD_FAILURE() << what << ": scalar reference wrote outside " << p.name;
        return;
      }
    }
  }
  ASSERT_FALSE(simd::Targets().empty());
  for (const simd::TargetKernels& t : simd::Targets()) {
    const std::vector<Plane> got = run(t.table);
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t i = 0; i < want.size(); ++i) {
      const auto mismatch = std::mismatch(want[i].bytes.begin(), want[i].bytes.end(), got[i].bytes.begin());
      if (mismatch.first != want[i].bytes.end()) {
        ADD_FAILURE() << what << " [" << t.name << "]: "
                      << DescribeMismatch(want[i], got[i], mismatch.first - want[i].bytes.begin());
      }
    }
  }
}

// ---- inputs

// An 8-bit image that may live inside a wider buffer (stride > width).
struct ImageCase {
  std::string name;
  cv::Mat buffer;  // owns the pixels
  cv::Mat image;   // the width x height view; image.step is the stride
  int out_pad = 0; // extra elements per output row, to test output strides > width
};

inline ImageCase Padded(std::string name, const cv::Mat& pixels, int in_pad, int out_pad) {
  ImageCase c;
  c.name = std::move(name);
  c.buffer = cv::Mat(pixels.rows, pixels.cols + in_pad, CV_8UC1, cv::Scalar(kSentinel));
  pixels.copyTo(c.buffer(cv::Rect(0, 0, pixels.cols, pixels.rows)));
  c.image = c.buffer(cv::Rect(0, 0, pixels.cols, pixels.rows));
  c.out_pad = out_pad;
  return c;
}

inline cv::Mat RandomImage(int width, int height, std::uint32_t seed, int lo = 0, int hi = 255) {
  cv::Mat m(height, width, CV_8UC1);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> dist(lo, hi);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) m.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(dist(rng));
  }
  return m;
}

// Random filled shapes on a random background: realistic edges in every direction.
inline cv::Mat ShapesImage(int width, int height, std::uint32_t seed) {
  std::mt19937 rng(seed);
  cv::Mat m(height, width, CV_8UC1, cv::Scalar(static_cast<int>(rng() % 256)));
  for (int i = 0; i < 40; ++i) {
    const cv::Point c(static_cast<int>(rng() % width), static_cast<int>(rng() % height));
    const cv::Size axes(5 + static_cast<int>(rng() % (width / 4 + 1)), 5 + static_cast<int>(rng() % (height / 4 + 1)));
    cv::ellipse(m, c, axes, static_cast<double>(rng() % 180), 0, 360, cv::Scalar(static_cast<int>(rng() % 256)), -1);
  }
  return m;
}

inline std::vector<std::string> DatasetImagePaths() {
  namespace fs = std::filesystem;
  std::vector<std::string> paths;
  const fs::path root = "../shared/datasets";
  std::error_code ec;
  if (!fs::is_directory(root, ec)) return paths;
  for (const auto& set : fs::directory_iterator(root, ec)) {
    const fs::path images = set.path() / "images";
    if (!fs::is_directory(images, ec)) continue;
    for (const auto& f : fs::directory_iterator(images, ec)) {
      if (f.is_regular_file()) paths.push_back(f.path().string());
    }
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

// The shared input set. Built once per test program.
inline const std::vector<ImageCase>& ConformanceImages() {
  static const std::vector<ImageCase> cases = [] {
    std::vector<ImageCase> c;
    std::uint32_t seed = 1;
    auto add = [&](std::string name, const cv::Mat& m, int in_pad = 0, int out_pad = 0) {
      c.push_back(Padded(std::move(name), m, in_pad, out_pad));
    };
    for (auto [w, h] : {std::pair{1, 1}, {2, 3}, {3, 2}, {7, 5}, {1, 9}, {9, 1}, {2, 2}}) {
      add("random " + std::to_string(w) + "x" + std::to_string(h), RandomImage(w, h, seed++));
    }
    // Every width from below one vector to above two vectors of the widest target (64 bytes).
    for (int w = 1; w <= 70; ++w) {
      add("random w=" + std::to_string(w) + " h=4", RandomImage(w, 4, seed++));
      add("low-contrast w=" + std::to_string(w) + " h=3 padded", RandomImage(w, 3, seed++, 120, 123), 5, 3);
    }
    for (int w : {17, 31, 33, 63, 65, 127, 129, 257}) {
      add("random w=" + std::to_string(w) + " padded", RandomImage(w, 9, seed++), 13, 7);
    }
    add("random 640x480", RandomImage(640, 480, seed++));
    add("random 1280x720", RandomImage(1280, 720, seed++));
    add("random 1920x1080", RandomImage(1920, 1080, seed++));
    add("shapes 640x480 padded", ShapesImage(640, 480, seed++), 32, 16);
    add("shapes 1281x721", ShapesImage(1281, 721, seed++));
    add("noise +-2 640x480", RandomImage(640, 480, seed++, 126, 130));
    for (int v : {0, 77, 255}) add("flat " + std::to_string(v) + " 64x48", cv::Mat(48, 64, CV_8UC1, cv::Scalar(v)));
    add("flat 200 640x480 padded", cv::Mat(480, 640, CV_8UC1, cv::Scalar(200)), 8, 8);
    for (const std::string& path : DatasetImagePaths()) {
      const cv::Mat m = cv::imread(path, cv::IMREAD_GRAYSCALE);
      if (!m.empty()) add(path, m);
    }
    return c;
  }();
  return cases;
}

// Scalar Sobel of an image case: realistic inputs for the kernels after it.
struct Gradients {
  int width = 0, height = 0;
  std::ptrdiff_t stride = 0;
  std::vector<std::int16_t> dx, dy;
  std::vector<std::uint16_t> mag;
};

inline Gradients GradientsOf(const ImageCase& c) {
  Gradients g;
  g.width = c.image.cols;
  g.height = c.image.rows;
  g.stride = g.width + c.out_pad;
  const std::size_t n = static_cast<std::size_t>(g.stride) * g.height;
  g.dx.assign(n, 0);
  g.dy.assign(n, 0);
  g.mag.assign(n, 0);
  ScalarKernels().sobel(c.image.data, static_cast<std::ptrdiff_t>(c.image.step), g.width, g.height,
                        g.dx.data(), g.dy.data(), g.mag.data(), g.stride);
  return g;
}

// The thresholds of g's frame in 64 px tiles (scalar histogram, then SelectThresholds with the
// default percentiles and contrast reference, but a floor of 8 instead of 40: some conformance
// images are small and dim, and their NMS maps should still hold edges).
inline CannyTiles TilesOf(const Gradients& g) {
  std::vector<std::uint32_t> hist(kMaxMagnitude + 1);
  CannyTiles tiles;
  tiles.Resize(g.width, g.height, kNmsMinTileShift + 1);
  ScalarKernels().magnitude_histogram(g.mag.data(), g.width, g.height, g.stride, tiles.shift, hist.data(),
                                      tiles.tile_max.data());
  SelectThresholds(hist.data(), 900, 400, 8, 200, &tiles);
  return tiles;
}

// Gradients with no image behind them: every dx, dy in [-range, range] (mag = |dx| + |dy|), so
// direction boundaries, zero components and ties between neighbours all occur.
inline Gradients RandomGradients(int width, int height, std::ptrdiff_t stride, int range, std::uint32_t seed) {
  Gradients g;
  g.width = width;
  g.height = height;
  g.stride = stride;
  const std::size_t n = static_cast<std::size_t>(stride) * height;
  g.dx.assign(n, 0);
  g.dy.assign(n, 0);
  g.mag.assign(n, 0);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> dist(-range, range);
  for (std::size_t i = 0; i < n; ++i) {
    g.dx[i] = static_cast<std::int16_t>(dist(rng));
    g.dy[i] = static_cast<std::int16_t>(dist(rng));
    g.mag[i] = static_cast<std::uint16_t>(std::abs(g.dx[i]) + std::abs(g.dy[i]));
  }
  return g;
}

inline std::string SizeOf(const ImageCase& c) {
  return c.name + " (" + std::to_string(c.image.cols) + "x" + std::to_string(c.image.rows) + ")";
}

}  // namespace ellipsekit::conformance
