// Frames and helpers shared by the benchmark files: the shared datasets' images, the scalar
// reference's edge-stage planes of a frame (inputs of the kernels, thresholds of the Canny
// baselines), throughput counters, and the release of what the benchmarks keep across runs.
#pragma once

#include <benchmark/benchmark.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

#include <opencv2/core.hpp>

#include "ellipsekit/types.h"
#include "kernels/canny_thresholds.h"

namespace ellipsekit::bench {

// Objects the benchmarks keep across runs in function-local statics (Detectors, Vulkan stages)
// are released by main after the benchmarks, not by static destructors: NVIDIA's Vulkan driver
// finalises itself in an exit handler of its own, and a vkDestroy* call after that crashes (an
// H200 with driver 580.159: ellipsekit_bench ended with SIGSEGV after its last benchmark). A
// cache registers its release when it is first filled; ReleaseBenchResources runs them, newest
// first.
void AtBenchEnd(std::function<void()> release);
void ReleaseBenchResources();

inline constexpr const char* kPrasadDir = "../shared/datasets/prasad_subset/images";
inline constexpr const char* kSharedDatasetsDir = "../shared/datasets";

// The .jpg/.jpeg/.png/.bmp files of `dir`, sorted; empty when it cannot be read.
std::vector<std::filesystem::path> ImagesIn(const std::filesystem::path& dir);
std::vector<std::filesystem::path> PrasadImages();
cv::Mat LoadGray(const std::filesystem::path& p);  // empty when unreadable
ImageView View(const cv::Mat& m);

// The inputs of every edge kernel for one frame size, produced by the scalar reference.
struct Prepared {
  cv::Mat frame;  // CV_8UC1, continuous
  int w = 0, h = 0;
  std::vector<std::uint8_t> blurred, nms, hyst, edges, scratch_u8;
  std::vector<std::int16_t> dx, dy;
  std::vector<std::uint16_t> mag;
  std::vector<std::uint32_t> hist;
  std::vector<std::int32_t> stack;
  CannyTiles tiles;   // the thresholds of every tile (nms reads them)
  CannyThresholds th;  // the frame's pair (tiles.frame), for the OpenCV baselines
};

// Fills *p from `frame` with the scalar reference kernels and the default options.
void PrepareFrom(const cv::Mat& frame, Prepared* p);

// The like-for-like baseline of detect()'s edge stage: the same 3x3 binomial blur (cv::GaussianBlur,
// 3x3, sigma 0: weights 1 2 1 / 4, replicated border) then cv::Canny with the L1 gradient and the
// thresholds `th` (those the edge stage picks on the frame). *blurred and *edges are scratch.
void BlurCanny(const cv::Mat& frame, const CannyThresholds& th, cv::Mat* blurred, cv::Mat* edges);

// items/s = pixels per iteration, bytes/s = bytes_per_iter per iteration.
void SetRates(benchmark::State& st, std::int64_t pixels, std::int64_t bytes_per_iter);

}  // namespace ellipsekit::bench
