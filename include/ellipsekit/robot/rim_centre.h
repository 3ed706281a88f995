// 3-D centre of a container's top rim from a registered depth image.
//
// The detector finds a top's outer rim. For a flat disc the depth inside the ellipse is the top
// itself (depth_sampling.h, SampleTopCentre: the interior median), but real containers are not flat
// there: a drink can's lid lies 3-6 mm below its rolled rim, a cup is open (inside is its far inner
// wall, its bottom or its contents), a jar's lid is narrower than its body. The interior median then
// puts the point on the lid floor / contents, below and behind the rim's centre. What the rim
// itself says is used instead:
//
//  1. Samples on the rim: about one per pixel of the outline's perimeter, each read at
//     `offsets_px` pixels inside and outside the fitted outline along its normal, back-projected to
//     3-D points X (camera frame).
//  2. Heights h = n . X along the plane normal n (towards the camera: larger is higher). Per side
//     (inside / outside), samples more than `off_object_m` below the side's 90th percentile are off
//     the object (table, background, the far inside of a cup). The rim is the highest surface at
//     the outline: the inner side holds it when the outline is the rim's outer edge (outside: the
//     side wall, lower, or the table), the outer side when the outline is an inner edge of the rim
//     (inside: the lid floor, lower). The side whose off-object-free median is higher is taken.
//  2b. With an expected centre (a tracked object's prediction): a taller object passing in front
//     hides part of the outline and is higher than the rim, so the highest side can be its top; a
//     level further than off_object_m from the expected height is tried again without the samples
//     above it, and the lower level is kept when it is nearer the expectation and its inliers cover
//     at least as many angle sectors (the occluder hides a part of the outline; the rim shows around the rest).
//  3. The rim level: mean shift on the heights with a Gaussian kernel as wide as the depth noise
//     (estimated from neighbouring samples), started at the side's upper quartile, so it settles on
//     the top mode (the rim) and not on the blend with a lid floor a few noise sigmas below.
//     Inliers: within `inlier_sigmas` of that level.
//  4. The plane n . X = d through the inliers (d their mean height; without a known normal, a
//     least-squares plane, trying both normals of the circle pose to seed the first gate).
//  5. The rim circle's centre: the ray through the projected circle centre (the pole of the
//     plane's vanishing line w.r.t. the ellipse; circle_pose.h) meets that plane.
//
// Why not the circle pose from a known radius fused with this depth: the radius fixes the distance
// only to ~1 % (0.87 % median on the project's renders, 6 mm at 0.7 m), while the plane through
// ~100-400 rim samples of 1-2 mm noise fixes it to a few tenths of a millimetre; fused, the
// depth term dominates and the radius adds an input the robot must know. The pole ray needs only
// the normal. (Measured in tests/test_robot_rim_centre.cc, README "Robot adapter".)
//
// Covariance: the plane offset's variance (inlier height variance / inliers) along the centre ray;
// the image error of the pole and the normal's error are not included.
//
// Frames: camera optical frame, metres. The sampler keeps its buffers, sized on the first call for
// the most samples an outline can give (max_angles): TrySample() then never allocates, also when it
// fails (the reason is kept; LastError() builds the message). Sample() allocates only the message
// of a failure.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "ellipsekit/robot/camera_model.h"
#include "ellipsekit/robot/messages.h"
#include "ellipsekit/types.h"

namespace ellipsekit::robot {

struct RimSampleOptions {
  std::array<double, 2> offsets_px{0.7, 1.4};  // read this far inside and outside the outline
  int min_angles = 48, max_angles = 1024;      // samples around the outline (~1 per pixel)
  double min_depth_m = 0.1, max_depth_m = 10.0;
  double off_object_m = 0.015;    // this far below a side's 90th percentile: not the object's top
  double inlier_sigmas = 2.0;     // inlier gate around the rim level, in depth-noise sigmas
  double min_noise_m = 0.0006;    // the noise estimate never falls below this (1 mm quantisation)
  int min_inliers = 12;
  int min_sectors = 4;            // of 16 angle sectors, with inliers (8 when the normal is fitted)
  std::optional<Eigen::Vector3d> plane_normal;  // camera frame, e.g. the table normal; else fitted
  // The rim centre expected (camera frame, e.g. a track's prediction; needs plane_normal): a level
  // found more than off_object_m from its height is an occluder's top in front of the rim, and the
  // samples above expected + off_object_m are left out (step 2b in rim_centre.cc).
  std::optional<Eigen::Vector3d> expected_centre;
  bool centre_from_circle = true;  // the circle through the inliers (else the pole ray, step 5)
  int min_circle_sectors = 8;      // of 16: fewer -> the pole ray
};

struct RimSample {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();   // rim circle centre, camera frame, metres
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // plane normal used, towards the camera
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // of the centre, m^2
  Eigen::Vector2d centre_pixel = Eigen::Vector2d::Zero();  // projected circle centre (raw pixels)
  double radius_m = 0;        // the outline back-projected onto the plane: mean distance to centre
  double noise_m = 0;         // depth noise estimate (height sigma)
  double plane_rms_m = 0;     // RMS height residual of the inliers
  int total_samples = 0;      // pixels read (both sides)
  int valid_samples = 0;      // with a valid depth
  int inliers = 0;            // on the rim plane: the samples used
  int sectors = 0;            // of 16 angle sectors holding inliers
  bool outer_side = false;    // the rim was outside the outline (the outline is an inner edge)
  Eigen::Vector3d pole_centre = Eigen::Vector3d::Zero();    // step 5's centre
  Eigen::Vector3d circle_centre = Eigen::Vector3d::Zero();  // the circle fit's (when has_circle)
  double circle_radius_m = 0;
  bool has_circle = false;
};

class RimCentreSampler {
 public:
  explicit RimCentreSampler(RimSampleOptions options = {}) : options_(options) {}
  const RimSampleOptions& options() const { return options_; }
  RimSampleOptions& mutable_options() { return options_; }

  // The ellipse is in raw pixels of `camera`; the depth image is registered to it. Fails on a bad
  // view or ellipse, bad options, or too few rim samples (the message says how many).
  Result<RimSample> Sample(const Ellipse& ellipse, const DepthImageView& depth, const CameraModel& camera);
  // The same without building a message: false on failure, *out untouched; LastError() says why.
  bool TrySample(const Ellipse& ellipse, const DepthImageView& depth, const CameraModel& camera, RimSample* out);
  // Why the last TrySample() failed (ok after a success).
  Status LastError() const;

 private:
  enum class Failure {
    kNone, kBadView, kBadEllipse, kBadOptions, kBadNormal, kTooFewValid, kTooFewOnPlane, kTooFewSectors,
    kEdgeOn, kBehind, kInner
  };
  struct Pt {
    Eigen::Vector3d X;
    float h;
    std::uint8_t outer;
    std::uint8_t sector;
  };
  RimSampleOptions options_;
  std::vector<Pt> pts_;
  std::vector<double> tmp_;
  std::vector<int> idx_;      // the inliers of the fit being run
  std::vector<int> fit_idx_;  // the inliers of the fit chosen so far
  Failure failure_ = Failure::kNone;
  int fail_valid_ = 0, fail_total_ = 0, fail_sectors_ = 0;
  Status inner_;  // kInner: the circle pose's or the projected centre's error
};

// Options of one top-centre estimate (the frame loop's choice).
enum class TopCentreMethod {
  kRimPlane,        // RimCentreSampler: containers (recessed lids, cups, jars) and flat discs
  kInteriorMedian,  // SampleTopCentre: the median depth inside the ellipse (flat discs only)
};

const char* TopCentreMethodName(TopCentreMethod m);

}  // namespace ellipsekit::robot
