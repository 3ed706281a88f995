#include "tools/eval/sensor_noise.h"

namespace ellipsekit::eval {

void AddSensorNoise(double sigma, std::uint64_t seed, cv::Mat* gray) {
  if (sigma <= 0) return;
  cv::Mat noise(gray->size(), CV_32F), sum;
  cv::RNG(seed).fill(noise, cv::RNG::NORMAL, 0, sigma);
  gray->convertTo(sum, CV_32F);
  sum += noise;
  sum.convertTo(*gray, CV_8U);  // rounded to nearest, saturated
}

std::uint64_t StemSeed(const std::string& stem) {
  std::uint64_t h = 14695981039346656037ull;
  for (const unsigned char ch : stem) h = (h ^ ch) * 1099511628211ull;
  return h;
}

}  // namespace ellipsekit::eval
