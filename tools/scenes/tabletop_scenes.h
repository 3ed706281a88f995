// The hard tabletop set (issue 18): 2-8 upright containers of five kinds (six with bottles) on a
// textured table among boxes and flat clutter, seen by a camera tilted 30-70 degrees from 0.4-1.2 m,
// with the exact image ellipse of every top's outer rim and, per top, its kind and how much of its
// rim is visible.
//
//   ellipsekit::scenes::TabletopScene s = ellipsekit::scenes::RenderTabletopScene(42);
//   // s.gray: 640x480 frame; s.truth[i]: the rim ellipse of top i; s.tops[i]: its kind, visibility
//
// Kinds (the container geometry of world.h / scene_generator.h's Container, reused):
//   can        a drink can (Container::kRecessedCan): rolled rim bead 2-3.5 mm wide, the lid's
//              floor 3-6 mm below it; a metal lid with glare in 40 % of cans
//   cup        an open ceramic cup (Container::kCupEmpty, one in four kCupFilled): the inside seen
//   jar        Container::kJar: a screw lid 4-8 mm narrower than the body, a shoulder below it;
//              the truth is the lid's top rim, not the shoulder
//   wood       a plain wooden cylinder: end grain on the top, long grain on the side, top and side
//              in one colour (low contrast: only the light tells them apart)
//   cardboard  a plain cardboard tube with a closed top, mottled, top and side in one colour
//   bottle     only with TabletopSceneOptions::bottles: Container::kBottle, 16-26 cm tall (a
//              rounded shoulder 2-4 cm high, a neck of the body's colour, a cap of radius 12-17 mm,
//              1.2-2.2 cm tall); the truth is the cap's top rim, a small ellipse high above the table
// The world: wood, cloth (woven, plaid bands), mottled or plain tables; soft shadows (penumbra
// growing with height); boxes, a share of them placed in front of a container so that they hide
// part of its top; flat printed shapes and lines on the table; tops allowed to run off the frame.
// Cans, cups and jars get the contrast fix of RenderScene (top albedos scaled until most of the rim
// shows an edge); wood and cardboard keep their low contrast.
//
// Truth: for each container, in placement order, the exact image ellipse of its top's outer rim
// (conic.h), also when part of it lies outside the frame or behind another object. A container is
// placed only if afterwards every top keeps a visible fraction >= min_visible_fraction, and its
// top's semi-minor axis is >= 5 px; so every rendered top is in the truth.
//
// Visible fraction of a top: the share of 360 points evenly spaced in angle around the rim circle
// (world space) whose projection lies inside the frame (-0.5 <= u < W - 0.5, same for v) and whose
// ray from the camera meets no other object (container or box) before the rim point; computed by
// the renderer's own ray caster.
//
// Dataset files (WriteTabletopDataset): images/ and gt/ exactly as WriteDataset (scene_generator.h),
// and DIR/meta/<stem>.txt with one line per gt line, in the same order:
//   <kind> <visible fraction>          e.g. "jar 0.8472"  ("%s %.4f")
// read by tools/eval/breakdown.h (`ellipsekit eval DIR --by kind,size,visibility`).
//
// Determinism as scene_generator.h: all randomness from splitmix64 seeded by `seed`, no threads.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "tools/scenes/scene_generator.h"

namespace ellipsekit::scenes {

enum class TabletopKind { kCan, kCup, kJar, kWood, kCardboard, kBottle };
inline constexpr int kTabletopKinds = 6;

// "can", "cup", "jar", "wood", "cardboard", "bottle".
const char* TabletopKindName(TabletopKind kind);
bool ParseTabletopKind(const std::string& name, TabletopKind* out);

struct TabletopSceneOptions {
  int width = 640, height = 480;
  int min_containers = 2, max_containers = 8;
  double min_tilt_deg = 30, max_tilt_deg = 70;        // optical axis against the table plane
  double min_distance_m = 0.4, max_distance_m = 1.2;  // camera to the table point at the image centre
  int max_boxes = 4;                                  // 0..max_boxes boxes, ~60 % of them occluders
  int clutter_shapes = 6;                             // flat printed shapes and lines
  double min_visible_fraction = 0.3;                  // every top keeps at least this much rim visible
  double edge_cut_share = 0.3;                        // share of placements that may run off the frame
  double noise_sigma = 3.0, blur_sigma = 0.8;         // as SceneOptions
  // Capped bottles among the kinds: each container is a bottle with probability kBottleShare, else
  // drawn as without them. false (the default) draws exactly the scenes of the fixed hard set.
  bool bottles = false;
};
inline constexpr double kBottleShare = 0.25;

struct TabletopTop {
  TabletopKind kind = TabletopKind::kCan;
  double visible_fraction = 1;   // see above
  double in_frame_fraction = 1;  // share of the rim points inside the frame (occluded or not)
  cv::Vec3d rim_centre;          // world metres (z up, the table is z = 0)
  double rim_radius_m = 0;       // the rim circle lies in the plane z = rim_centre[2]
};

struct TabletopScene {
  cv::Mat gray;                            // CV_8UC1
  std::vector<ellipsekit::Ellipse> truth;  // one per top, the outer rim
  std::vector<TabletopTop> tops;           // same order as truth
  cv::Matx33d K, R;                        // camera: x ~ K (R X + t), X world
  cv::Vec3d t;
};

// Ok, or kInvalidArgument naming the bad field (size 64..8192, 1 <= min_containers <=
// max_containers <= 20, 0 < min_tilt <= max_tilt <= 85, 0.1 <= min_distance <= max_distance <= 10,
// max_boxes 0..20, clutter_shapes 0..1000, min_visible_fraction 0.05..1, edge_cut_share 0..1,
// sigmas as SceneOptions).
ellipsekit::Status ValidateTabletopSceneOptions(const TabletopSceneOptions& options);

// Renders one scene; invalid options give an empty scene (gray.empty()).
TabletopScene RenderTabletopScene(std::uint64_t seed, const TabletopSceneOptions& options = {});

// images/, gt/ (WriteDataset: scene i = RenderTabletopScene(MixSeed(seed, i))) and meta/ (above).
ellipsekit::Status WriteTabletopDataset(const std::string& dir, int count, std::uint64_t seed,
                                        const TabletopSceneOptions& options = {});

// One meta line, "%s %.4f" (no newline).
std::string FormatTabletopMetaLine(const TabletopTop& top);

}  // namespace ellipsekit::scenes
