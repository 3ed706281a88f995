// The fuzz entry shared by the libFuzzer target (fuzz_detect) and the corpus replay (fuzz_detect_replay).
#pragma once

#include <cstddef>
#include <cstdint>

namespace ellipsekit::fuzz {

// Decodes `data` into an image size, stride, options and pixels, runs Detector::detect() on every
// backend that is available here, and checks what comes back. Aborts (so that the fuzzer or the
// replay reports it) when an invariant is broken: ok for an invalid input, an error for a valid
// one on the always-available scalar backend, an ellipse with non-finite or inconsistent fields.
// Returns 0.
int DetectOneInput(const std::uint8_t* data, std::size_t size);

}  // namespace ellipsekit::fuzz
