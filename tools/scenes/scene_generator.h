// Synthetic test scenes: upright cylinders (cans, cups, jars) standing on a textured table, seen by a
// tilted pinhole camera, rendered by ray casting, with the exact image ellipse of every visible top.
//
//   ellipsekit::scenes::Scene s = ellipsekit::scenes::RenderScene(42);
//   // s.gray: CV_8UC1 photo-like frame; s.truth: one ellipse per visible cylinder top.
//
// Conventions (DESIGN.md): pixel centres at integer coordinates, x right, y down; the ray of pixel
// (x, y) passes through image point (x, y) exactly. Ellipse (cx, cy, a, b, theta): a >= b,
// major axis along (cos theta, sin theta), theta in [-pi/2, pi/2). score is 0 in ground truth.
//
// Ground truth is exact: the top rim (a circle on a plane parallel to the table) maps to the image
// by a homography H, and its image is the conic H^-T diag(1,1,-1) H^-1 (see conic.h). Every top in
// `truth` has at least 50 % of its rim unoccluded (100 % when occlusion is off); objects whose top
// would be less visible are re-placed or dropped, so no rendered top is missing from `truth`.
//
// Determinism: all randomness comes from a private splitmix64 generator seeded by `seed`, so the
// same seed and options give identical pixels and truth (no std:: distributions, no threads).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "ellipsekit/types.h"

namespace ellipsekit::scenes {

struct SceneOptions {
  int width = 640, height = 480;
  double min_tilt_deg = 30, max_tilt_deg = 70;  // camera tilt: angle between optical axis and the table plane
  int min_objects = 1, max_objects = 5;         // upright cylinders (cans, cups)
  bool occlusion = true;                        // allow partial occlusion of tops (by other cylinders / clutter)
  int clutter_shapes = 6;                       // boxes, flat printed shapes and lines on the table
  double noise_sigma = 3.0;                     // gray levels, additive Gaussian
  double blur_sigma = 0.8;                      // px
};

struct Scene {
  cv::Mat gray;                           // CV_8UC1, width x height
  std::vector<ellipsekit::Ellipse> truth;  // one per visible cylinder top (score field unused = 0)
};

// Ok, or kInvalidArgument naming the bad field (size 16..8192, 0 < tilt <= 90, min <= max, counts >= 0,
// sigmas >= 0 and finite).
ellipsekit::Status ValidateSceneOptions(const SceneOptions& options);

// Renders one scene. Invalid options (see ValidateSceneOptions) give an empty Scene (gray.empty()).
// Fewer than min_objects cylinders may appear when they cannot be placed visibly (rare).
Scene RenderScene(std::uint64_t seed, const SceneOptions& options = {});

// Writes DIR/images/scene_NNNN.png and DIR/gt/scene_NNNN.txt (N = 0..count-1, 4 digits); scene i is
// RenderScene(MixSeed(seed, i)). A GT file holds one line "cx cy a b theta" per top ("%.4f %.4f %.4f
// %.4f %.6f"), and is empty for a scene without tops. Creates folders; writes each file to a temporary
// name in the same folder, then renames it; returns a Status naming the problem on failure.
ellipsekit::Status WriteSceneDataset(const std::string& dir, int count, std::uint64_t seed,
                                     const SceneOptions& options = {});

// A well-mixed 64-bit seed for scene `index` of a dataset seeded with `seed`.
std::uint64_t MixSeed(std::uint64_t seed, std::uint64_t index);

// One ground-truth line, "%.4f %.4f %.4f %.4f %.6f" (no newline).
std::string FormatTruthLine(const ellipsekit::Ellipse& e);

}  // namespace ellipsekit::scenes
