// Helpers for the tests that check whole stages against the scalar reference
// (conformance_vulkan_edge.cc, conformance_vulkan_arcs.cc, conformance_arc_inputs.h): the scalar
// edge stage and curve tracing exactly as runtime/detector.cc runs them, and the guard that gives a
// Vulkan test one stage per test binary and skips it without a device (a failure under CI=true).
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "ellipsekit/options.h"
#include "ellipsekit/types.h"
#include "fit/curve_tracing.h"
#include "kernels/arc_types.h"
#include "kernels/canny_thresholds.h"
#include "kernels/edge_sign.h"
#include "kernels/gaussian.h"
#include "kernels/hysteresis.h"
#include "kernels/nms.h"
#include "kernels/sobel.h"

namespace ellipsekit::stage_test {

inline ImageView ViewOf(const cv::Mat& gray) {
  return ImageView{gray.data, gray.cols, gray.rows, static_cast<std::ptrdiff_t>(gray.step)};
}

struct Edges {
  std::vector<std::int16_t> dx, dy;
  std::vector<std::uint8_t> edge_map;
  std::vector<std::uint32_t> hist;  // the magnitude histogram the thresholds were picked from
  CannyTiles tiles;                 // the thresholds: tiles.frame the frame's, tiles.high / low each tile's
};

// The scalar edge stage exactly as runtime/detector.cc runs it (the Gaussian only with
// o.gaussian_blur); out's vectors are resized to width * height.
inline void ScalarEdges(const ImageView& image, const Options& o, Edges* out) {
  const int w = image.width, h = image.height;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  std::vector<std::uint8_t> blurred(n), nms(n);
  std::vector<std::uint16_t> mag(n);
  std::vector<std::int32_t> stack(n);
  out->hist.assign(kMaxMagnitude + 1, 0);
  out->dx.assign(n, 0);
  out->dy.assign(n, 0);
  out->edge_map.assign(n, 0);
  const std::uint8_t* src = image.data;
  std::ptrdiff_t src_stride = image.stride;
  if (o.gaussian_blur) {
    scalar::Gaussian(image.data, image.stride, w, h, blurred.data(), w);
    src = blurred.data();
    src_stride = w;
  }
  scalar::Sobel(src, src_stride, w, h, out->dx.data(), out->dy.data(), mag.data(), w);
  out->tiles.Resize(w, h, o);
  scalar::MagnitudeHistogram(mag.data(), w, h, w, out->tiles.shift, out->hist.data(), out->tiles.tile_max.data());
  SelectThresholds(out->hist.data(), o, &out->tiles);
  scalar::Nms(out->dx.data(), out->dy.data(), mag.data(), w, h, w, out->tiles.view(), nms.data(), w);
  scalar::Hysteresis(nms.data(), w, h, w, stack.data());
  scalar::EdgeSign(nms.data(), w, out->dx.data(), out->dy.data(), w, w, h, out->edge_map.data(), w);
}

// The curves of at least min_points points traced from ScalarEdges (before the detector's OBB filter).
inline Curves ScalarCurves(const ImageView& image, const Options& o, int min_points) {
  Edges e;
  ScalarEdges(image, o, &e);
  const int w = image.width;
  Curves curves;
  TraceScratch trace;
  TraceCurves(e.edge_map.data(), w, e.dx.data(), e.dy.data(), w, w, image.height, min_points, &curves, &trace);
  return curves;
}

inline bool InCi() {
  const char* ci = std::getenv("CI");
  return ci != nullptr && std::string(ci) == "true";
}

// One Stage (VulkanEdgeStage, VulkanArcStage) for the whole binary: creating a device per test
// would dominate the run time. nullptr, with *why set, when Stage::Create failed.
template <class Stage>
Stage* SharedStage(std::string* why) {
  static std::unique_ptr<Stage> stage;
  static Status status = Stage::Create(&stage);
  *why = status.message();
  return stage.get();
}

}  // namespace ellipsekit::stage_test

// Declares `Stage* var` for a test body; skips the test when there is none, or fails it under
// CI=true (CI has lavapipe). `what` names the missing thing in the message.
#define REQUIRE_VULKAN_STAGE(Stage, var, what)                                         \
  std::string why_;                                                                    \
  Stage* var = ::ellipsekit::stage_test::SharedStage<Stage>(&why_);                    \
  if (var == nullptr) {                                                                \
    if (::ellipsekit::stage_test::InCi()) FAIL() << "CI=true but no " what ": " << why_; \
    GTEST_SKIP() << why_;                                                              \
  }
