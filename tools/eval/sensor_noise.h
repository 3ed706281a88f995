// Sensor noise for measuring robustness: white Gaussian noise of standard deviation `sigma` grey
// levels added to an 8-bit frame, rounded to nearest and saturated, drawn from cv::RNG(seed).
// `ellipsekit eval --noise` seeds it with StemSeed(image stem), so a frame gets the same noise
// whatever the dataset's order, run or machine (docs/noise.md).
#pragma once

#include <cstdint>
#include <string>

#include <opencv2/core.hpp>

namespace ellipsekit::eval {

// gray: CV_8UC1, changed in place. sigma >= 0 (0 leaves it as it is).
void AddSensorNoise(double sigma, std::uint64_t seed, cv::Mat* gray);

// FNV-1a of the stem's bytes.
std::uint64_t StemSeed(const std::string& stem);

}  // namespace ellipsekit::eval
