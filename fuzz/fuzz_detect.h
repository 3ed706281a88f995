// The fuzz entries shared by the libFuzzer targets and their corpus replays:
//   DetectOneInput      fuzz_detect, fuzz_detect_replay (fuzz_detect.cc)
//   DetectCpuOneInput   fuzz_detect_cpu, fuzz_detect_cpu_replay (fuzz_detect_cpu.cc)
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

// CPU only (no Vulkan), small frames (at most 128 x 96), fast: decodes `data` into options and a
// raw or drawn (ellipses, rings, a grid of dots) frame, runs the scalar and the SIMD backend on it
// and aborts unless both agree bit for bit (ellipses and counts) and pass the checks above.
// Returns 0.
int DetectCpuOneInput(const std::uint8_t* data, std::size_t size);

}  // namespace ellipsekit::fuzz
