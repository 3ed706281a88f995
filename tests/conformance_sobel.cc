// sobel: every Highway target is bit-identical to the scalar reference (kernels/sobel.h).
#include <gtest/gtest.h>

#ifdef ELLIPSEKIT_HAVE_SIMD
#include "tests/conformance_util.h"

namespace ellipsekit::conformance {
namespace {

TEST(ConformanceSobel, AllImagesAllTargets) {
  for (const ImageCase& c : ConformanceImages()) {
    const int w = c.image.cols, h = c.image.rows;
    const std::ptrdiff_t stride = w + c.out_pad;
    ExpectAllTargetsMatchScalar("sobel " + SizeOf(c), [&](const KernelTable& k) {
      std::vector<Plane> out;
      out.push_back(MakePlane<std::int16_t>("dx", w, h, stride));
      out.push_back(MakePlane<std::int16_t>("dy", w, h, stride));
      out.push_back(MakePlane<std::uint16_t>("mag", w, h, stride));
      k.sobel(c.image.data, static_cast<std::ptrdiff_t>(c.image.step), w, h, out[0].data<std::int16_t>(),
              out[1].data<std::int16_t>(), out[2].data<std::uint16_t>(), stride);
      return out;
    });
  }
}

// The extremes: a one-pixel checkerboard of 0 and 255 reaches |dx|, |dy| = 1020 nowhere but a
// 0/255 step does; both are in here.
TEST(ConformanceSobel, ExtremeValues) {
  cv::Mat step(16, 67, CV_8UC1, cv::Scalar(0));
  step(cv::Rect(33, 0, 34, 16)).setTo(255);
  step(cv::Rect(0, 8, 67, 8)).setTo(255);
  cv::Mat checker(16, 67, CV_8UC1);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 67; ++x) checker.at<std::uint8_t>(y, x) = ((x + y) & 1) ? 255 : 0;
  for (const cv::Mat& m : {step, checker}) {
    const ImageCase c = Padded("extreme", m, 3, 5);
    const int w = m.cols, h = m.rows;
    const std::ptrdiff_t stride = w + c.out_pad;
    ExpectAllTargetsMatchScalar("sobel extreme", [&](const KernelTable& k) {
      std::vector<Plane> out;
      out.push_back(MakePlane<std::int16_t>("dx", w, h, stride));
      out.push_back(MakePlane<std::int16_t>("dy", w, h, stride));
      out.push_back(MakePlane<std::uint16_t>("mag", w, h, stride));
      k.sobel(c.image.data, static_cast<std::ptrdiff_t>(c.image.step), w, h, out[0].data<std::int16_t>(),
              out[1].data<std::int16_t>(), out[2].data<std::uint16_t>(), stride);
      return out;
    });
  }
}

}  // namespace
}  // namespace ellipsekit::conformance
#else
TEST(ConformanceSobel, SimdNotBuilt) { GTEST_SKIP() << "Highway not found at configure time"; }
#endif
