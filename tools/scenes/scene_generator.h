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

#include <array>
#include <cstdint>
#include <functional>
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

// The same files for scenes of any generator: scene i is render(MixSeed(seed, i)); count 0..10000.
ellipsekit::Status WriteDataset(const std::string& dir, int count, std::uint64_t seed,
                                const std::function<Scene(std::uint64_t)>& render);

// A well-mixed 64-bit seed for scene `index` of a dataset seeded with `seed`.
std::uint64_t MixSeed(std::uint64_t seed, std::uint64_t index);

// One ground-truth line, "%.4f %.4f %.4f %.4f %.6f" (no newline).
std::string FormatTruthLine(const ellipsekit::Ellipse& e);

// ---------------------------------------------------------------- container geometry (sequences)
// What rides the conveyor or stands in a stacking / crossing scene. kFlatCan is the original can (a
// flat lid with a printed rim ring; the default, so the default scenes stay as they were); the
// others are real container geometry, each with its own random shape drawn from a separate stream
// (placement, camera, clutter and colours are those of the same seed's flat can):
//   kRecessedCan  a drink can: rolled rim bead 2-3.5 mm wide at the top, the lid's floor 3-6 mm
//                 below it (metal: inner wall and floor in the lid's colour, lit from the open top)
//   kCupEmpty     an open cup, wall 2-4 mm, inner floor 6-12 mm above the table
//   kCupFilled    the same cup filled to 45-85 % of its height (contents unlike the inner wall)
//   kJar          a body with a shoulder and a screw lid 4-8 mm narrower in radius, 8-14 mm tall
//   kBottle       a body, a rounded shoulder (2-4 cm) narrowing to a neck (1-3 cm) of the body's
//                 colour, and a cap (1.2-2.2 cm) of radius 12-17 mm; the three scaled down alike
//                 where they would take more than 0.55 of the height (a short bottle)
// metal_top makes the lid (and a recessed lid's floor) strongly specular. The rim circle (truth) is
// the top edge of the outermost ring seen from above: the can's rim bead, the cup's lip, the jar's
// lid, the bottle's cap; centre at the top height, normal +z (world), radius rim_radius_m.
enum class Container { kFlatCan, kRecessedCan, kCupEmpty, kCupFilled, kJar, kBottle };

// "flat-can", "recessed-can", "cup", "filled-cup", "jar", "bottle".
const char* ContainerName(Container c);
// The inverse of ContainerName; false for an unknown name.
bool ParseContainer(const std::string& name, Container* out);

struct RimCircle {
  cv::Vec3d centre;               // world metres
  cv::Vec3d normal{0, 0, 1};      // world, unit
  double radius = 0;              // metres
};

// ---------------------------------------------------------------- conveyor sequences
// One can riding a straight guide on the table (same ray caster, camera, light, table and flat
// clutter as RenderScene; no boxes, so nothing occludes the can). The can starts at the guide's
// start end at t = 0, moves at `speed_m_s` and turns round at each end (the paper's return phase):
// position along the guide s(t) is a triangle wave between 0 and the guide's length.
// Depth: z (metres along the camera axis) of the first hit at each pixel centre, plus Gaussian
// noise of sigma depth_noise_mm * (1 + z^2 / 1 m^2), quantised to 1 mm; a share
// depth_invalid_fraction of pixels, and about half of the pixels at depth jumps > 2 cm, read 0
// (invalid), as do pixels that see no surface.
struct ConveyorSceneOptions {
  int width = 640, height = 480;
  double speed_m_s = 0.05;        // > 0
  double fps = 30;                // frames per second
  int frames = 90;                // 3 s at 30 fps
  double guide_length_m = 0.25;   // shortened when the can would leave the image
  int clutter_shapes = 5;         // flat printed shapes and lines on the table
  double noise_sigma = 3.0, blur_sigma = 0.8;  // as SceneOptions
  double depth_noise_mm = 1.0;
  double depth_invalid_fraction = 0.01;
  Container container = Container::kFlatCan;  // what rides the guide (see Container)
  bool metal_top = false;
  // Shutter time, s, 0 <= exposure_s <= 1 / fps: each image averages the scene over
  // [t - exposure_s / 2, t + exposure_s / 2] (motion blur along the guide; 16 sub-frames); the
  // truth and the depth image are at t. 0: every image is a still at t.
  double exposure_s = 0;
};

struct ConveyorFrame {
  int index = 0;
  double t = 0;                  // seconds
  cv::Mat gray;                  // CV_8UC1
  cv::Mat depth_mm;              // CV_16UC1, millimetres along the camera z axis, 0 = invalid
  cv::Vec3d top_centre;          // true top centre, world metres
  cv::Vec2d top_pixel;           // its projection (pixels)
  ellipsekit::Ellipse truth;     // exact image ellipse of the top rim
  RimCircle rim;                 // the rim circle (centre == top_centre)
};

struct ConveyorSequence {
  int width = 0, height = 0;
  cv::Matx33d K;                 // pinhole, no distortion
  cv::Matx44d T_world_camera;    // world = T * camera (camera optical frame: x right, y down, z forward)
  cv::Vec3d start_point, end_point;  // top centre at each end of the guide, world metres
  cv::Vec2d start_pixel, end_pixel;  // their projections
  double speed_m_s = 0, length_m = 0, radius_m = 0, height_m = 0, fps = 30;
  int frames = 0;
  Container container = Container::kFlatCan;
  double rim_radius_m = 0;       // the rim circle's radius (radius_m but for a jar's lid)
  double recess_m = 0;           // recessed can: lid floor below the rim; filled cup: fill below the lip

  // Position along the guide (metres from the start end) and the true top centre at time t
  // (any t >= 0, also beyond the last frame).
  double PositionAt(double t) const;
  cv::Vec3d TopCentreAt(double t) const;
};

// Ok, or kInvalidArgument naming the bad field.
ellipsekit::Status ValidateConveyorOptions(const ConveyorSceneOptions& options);

// Renders the sequence frame by frame, calling `sink` for each (in order); stops at the first
// non-ok Status from the sink and returns it. `info` (optional) receives the camera and guide.
ellipsekit::Status RenderConveyorSequence(std::uint64_t seed, const ConveyorSceneOptions& options,
                                          ConveyorSequence* info,
                                          const std::function<ellipsekit::Status(const ConveyorFrame&)>& sink);

// Writes a sequence directory: frames/NNNNNN.png, depth/NNNNNN.png (uint16 mm), timestamps.txt (one
// time in seconds per line), camera.json {"width", "height", "K" (9, row-major), "D" (5 zeros),
// "T_world_camera" (16, row-major)}, conveyor.json {"references": [{"point": [x, y, z], "pixel":
// [u, v]} x 2]} and truth.jsonl (one line per frame: {"t": T, "tops": [{"centre": [x, y, z],
// "pixel": [u, v], "ellipse": [cx, cy, a, b, theta]}]}). Files are written under temporary names,
// then renamed.
ellipsekit::Status WriteConveyorSequence(const std::string& dir, std::uint64_t seed,
                                         const ConveyorSceneOptions& options = {},
                                         ConveyorSequence* info = nullptr);

// ---------------------------------------------------------------- stacking and crossing sequences
// Two cans in the conveyor world (same camera model, light, table and flat clutter; no boxes), for
// the stacking task and the tracker:
//  - static (speed_m_s == 0): the cans stand still, can 0 on the feed side (right half of the image)
//    and can 1 on the stack side (left half); every frame is the same rendering with independent
//    image noise and depth noise;
//  - crossing (speed_m_s > 0): the cans ride two parallel lanes roughly along the image rows, in
//    opposite directions, and pass each other at mid-sequence. The lanes are r0 + r1 + lane_gap_m
//    apart (the cans clear each other by lane_gap_m); can 0 rides the lane nearer the camera. With
//    crossing_height_difference_m > 0 can 0 is that much taller, so near the crossing its top
//    rises into the image of can 1's top and hides part of it.
// The camera's distance to the tops (along the optical axis, at the image centre) is drawn from
// [min_distance_m, max_distance_m]; the tilt from [min_tilt_deg, max_tilt_deg]. Depth as in the
// conveyor sequences.
struct CanSceneOptions {
  int width = 640, height = 480;
  double fps = 30;
  int frames = 20;
  double speed_m_s = 0;             // 0: static; > 0: crossing
  double lane_gap_m = 0.01;         // crossing: clearance between the cans when they pass
  double crossing_height_difference_m = 0;  // crossing: can 0 (near lane) is taller by this much
  double min_radius_m = 0.03, max_radius_m = 0.04;
  double min_height_m = 0.08, max_height_m = 0.12;
  double min_distance_m = 0.5, max_distance_m = 1.0;
  double min_tilt_deg = 45, max_tilt_deg = 65;
  int clutter_shapes = 5;
  double noise_sigma = 3.0, blur_sigma = 0.8;
  double depth_noise_mm = 1.0;
  double depth_invalid_fraction = 0.01;
  std::array<Container, 2> containers{Container::kFlatCan, Container::kFlatCan};  // can 0, can 1
  bool metal_top = false;
};

struct CanFrame {
  int index = 0;
  double t = 0;
  cv::Mat gray;                            // CV_8UC1
  cv::Mat depth_mm;                        // CV_16UC1, millimetres along the camera z axis, 0 = invalid
  std::vector<cv::Vec3d> top_centre;       // per can: true top centre, world metres
  std::vector<cv::Vec2d> top_pixel;        // its projection
  std::vector<ellipsekit::Ellipse> truth;  // exact image ellipse of each top rim
  std::vector<double> rim_visible;         // share of each top rim not hidden by the other can
  std::vector<RimCircle> rim;              // per can: the rim circle (centre == top_centre)
};

struct CanSequence {
  int width = 0, height = 0;
  cv::Matx33d K;                  // pinhole, no distortion
  cv::Matx44d T_world_camera;     // world = T * camera
  double fps = 30;
  int frames = 0;
  std::vector<double> radius_m, height_m;   // per can
  // Per can: the lid's rim ring is rim_width_m wide (0 without one); the top's image then has
  // edges at radius_m, radius_m - rim_width_m and (the countersink groove) 2 mm further in.
  std::vector<double> rim_width_m;
  std::vector<Container> container;         // per can
  std::vector<double> rim_radius_m;         // per can: the rim circle's radius
  std::vector<cv::Vec3d> start_point;       // top centre at t = 0, world metres
  std::vector<cv::Vec3d> velocity_m_s;      // world; zero for a static scene

  cv::Vec3d TopCentreAt(int can, double t) const;
};

// Ok, or kInvalidArgument naming the bad field.
ellipsekit::Status ValidateCanSceneOptions(const CanSceneOptions& options);

// Renders the sequence frame by frame (see RenderConveyorSequence). Fails with kInternal when the
// cans cannot be placed in view (image too small, crossing too long for the image).
ellipsekit::Status RenderCanSequence(std::uint64_t seed, const CanSceneOptions& options, CanSequence* info,
                                     const std::function<ellipsekit::Status(const CanFrame&)>& sink);

// Writes a sequence directory as WriteConveyorSequence does (frames/, depth/, timestamps.txt,
// camera.json, truth.jsonl with one entry per can in "tops"; no conveyor.json).
ellipsekit::Status WriteCanSequence(const std::string& dir, std::uint64_t seed, const CanSceneOptions& options = {},
                                    CanSequence* info = nullptr);

}  // namespace ellipsekit::scenes
