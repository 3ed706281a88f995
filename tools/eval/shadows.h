// Soft shadows for measuring local contrast: three round shadows darken an 8-bit frame, each
// multiplying the grey levels by `gain` inside 0.7 of its radius and by a factor rising linearly
// to 1 between 0.7 and 1.3 radii (overlaps take the darker factor); centres uniform over the
// frame, radii 0.15-0.35 of its width, drawn from cv::RNG(seed). `ellipsekit eval --shadow` seeds
// it with StemSeed(image stem) (sensor_noise.h), so a frame gets the same shadows on every run
// (docs/contrast.md).
#pragma once

#include <cstdint>

#include <opencv2/core.hpp>

namespace ellipsekit::eval {

// gray: CV_8UC1, changed in place (rounded to nearest). gain in (0, 1]; 1 leaves it as it is.
void AddShadows(double gain, std::uint64_t seed, cv::Mat* gray);

}  // namespace ellipsekit::eval
