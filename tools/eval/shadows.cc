#include "tools/eval/shadows.h"

#include <algorithm>
#include <cmath>

namespace ellipsekit::eval {

void AddShadows(double gain, std::uint64_t seed, cv::Mat* gray) {
  if (gain >= 1) return;
  constexpr int kShadows = 3;
  cv::RNG rng(seed);
  cv::Mat factor(gray->size(), CV_32F, cv::Scalar(1.0));
  for (int k = 0; k < kShadows; ++k) {
    const double cx = rng.uniform(0.0, 1.0) * gray->cols, cy = rng.uniform(0.0, 1.0) * gray->rows;
    const double r = rng.uniform(0.15, 0.35) * gray->cols;
    for (int y = 0; y < gray->rows; ++y) {
      float* f = factor.ptr<float>(y);
      for (int x = 0; x < gray->cols; ++x) {
        const double d = std::hypot(x - cx, y - cy) / r;
        const double core = std::clamp((1.3 - d) / 0.6, 0.0, 1.0);  // 1 inside 0.7 r, 0 outside 1.3 r
        f[x] = std::min(f[x], static_cast<float>(1 - (1 - gain) * core));
      }
    }
  }
  cv::Mat shaded;
  gray->convertTo(shaded, CV_32F);
  shaded = shaded.mul(factor);
  shaded.convertTo(*gray, CV_8U);  // rounded to nearest
}

}  // namespace ellipsekit::eval
