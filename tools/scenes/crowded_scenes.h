// Crowded scenes: one flat layout of many circles seen through a tilted pinhole camera — calibration
// grids of dots or rings, crates of can tops, trays of bottle caps, trays of open cups seen from
// above — with the exact image ellipse of every circle in the truth.
//
//   ellipsekit::scenes::Scene s = ellipsekit::scenes::RenderCrowdedScene(42);
//
// Every circle lies on one plane (a printed target, or the tops of same-height objects packed in a
// crate: a top can then only be hidden by something above that plane, and there is none), so the
// plane maps to the image by one homography H and each circle's image is exactly the conic
// H^-T C H^-1 (conic.h). Conventions as scene_generator.h: pixel centres at integers, the ray of
// pixel (x, y) passes through image point (x, y); ellipses a >= b, theta in [-pi/2, pi/2).
//
// What the truth holds: every dot; both edges of every ring (outer and inner circle); the outer rim
// of every can, cap and cup (the lid's inner ring, groove and a cup's inner lip are edges too, but,
// as in scene_generator.h, a top's truth is its outer rim). The whole layout lies inside the frame.
// With CrowdedSceneOptions::clutter, bars and cables lie above the layout and hide parts of it.
//
// Variety per scene (all drawn from the seed): layout, frame size, rows x columns (8x6 up to 20x15
// for the grids; 50-300 objects, fewer where the frame is too small to show them at >= 48 px
// pitch), hexagonal or square packing, objects touching or apart, camera tilt 0-max_tilt_deg off
// the plane's normal at any azimuth and roll, perspective strength, uneven light, glare spots on
// metal and ceramic, lens blur 0.5-1.5 px and noise 1.5-5 gray levels; every truth ellipse's
// semi-minor axis >= min_semi_minor_px (below). Deterministic as
// scene_generator.h (splitmix64, no threads).
#pragma once

#include <cstdint>
#include <string>

#include "tools/scenes/scene_generator.h"

namespace ellipsekit::scenes {

enum class CrowdedLayout {
  kAny,       // drawn per scene from the five below
  kDotGrid,   // dark dots printed on paper
  kRingGrid,  // dark rings printed on paper (two truth ellipses each)
  kCanCrate,  // can tops (bright rolled rim, recessed lid with a groove) packed in a crate
  kCapTray,   // bottle caps (knurled edge, one colour each) on a tray
  kCupTray,   // open cups from above (thin bright lip, dark inside)
};

struct CrowdedSceneOptions {
  int width = 0, height = 0;      // 0 x 0: drawn per scene from 640x480, 1280x720, 1920x1080
  CrowdedLayout layout = CrowdedLayout::kAny;
  int objects = 0;                // dots, rings or tops in the layout; 0: drawn from 50..300 (see above)
  double max_tilt_deg = 60;       // camera tilt off the plane's normal, drawn from [0, max_tilt_deg]
  // The camera is drawn again while the smallest truth ellipse's semi-minor axis is below this
  // (px; up to 30 draws, then the draw closest to it is kept). 10 px: a quarter of a smaller
  // ellipse is shorter than the paper's T_n = 15 edge points, so its arcs never reach grouping.
  // 0: no floor.
  double min_semi_minor_px = 10;
  // Rings: inner radius / outer radius, drawn per scene from this range. Above 1 / 1.45 = 0.69
  // the detector takes the outer edge for the rim of the inner one and reports one ellipse (the
  // rule for can tops, fit/clustering.h IsOuterRim).
  double min_ring_ratio = 0.45, max_ring_ratio = 0.7;
  // Things above and beside the layout: 1-3 bars (a gripper's finger, a ruler, an arm; shaded
  // across their width), 0-2 cables 3-10 px thick, and 6-20 printed marks (strokes, labels) on
  // the table around the board. A circle stays in the truth when at least kClutterMinVisible of
  // its rim (360 points) is not hidden by a bar or a cable.
  bool clutter = false;
};

inline constexpr double kClutterMinVisible = 0.5;

// Ok, or kInvalidArgument naming the bad field (size both 0 or 64..8192, objects 0..2000,
// 0 <= max_tilt_deg <= 70, 0 <= min_semi_minor_px <= 100, 0.1 <= min_ring_ratio <= max_ring_ratio
// <= 0.9).
ellipsekit::Status ValidateCrowdedSceneOptions(const CrowdedSceneOptions& options);

// Renders one crowded scene; invalid options give an empty Scene (gray.empty()).
Scene RenderCrowdedScene(std::uint64_t seed, const CrowdedSceneOptions& options = {});

// As WriteSceneDataset (images/, gt/, scene i = RenderCrowdedScene(MixSeed(seed, i))).
ellipsekit::Status WriteCrowdedDataset(const std::string& dir, int count, std::uint64_t seed,
                                       const CrowdedSceneOptions& options = {});

// "any", "dots", "rings", "cans", "caps", "cups".
const char* CrowdedLayoutName(CrowdedLayout layout);
bool ParseCrowdedLayout(const std::string& name, CrowdedLayout* layout);

}  // namespace ellipsekit::scenes
