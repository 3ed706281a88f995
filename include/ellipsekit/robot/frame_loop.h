// The robot loop in one call per frame: detect -> track -> 3-D rim centres -> conveyor -> grasp.
//
//   ellipsekit::robot::FrameLoopOptions opt;
//   opt.T_world_camera = ...;                    // output frame (e.g. base_link) from the camera
//   opt.conveyor = {{start_ref, end_ref}};       // optional: objects riding a linear guide
//   ellipsekit::robot::FrameLoop loop(camera, opt);
//   if (!loop.status().ok()) ...
//   ellipsekit::robot::FrameOutput out;
//   for (each frame) {
//     Status s = loop.ProcessFrame(gray_view, &depth_view /* or nullptr */, stamp_s, &out);
//     for (const TrackOutput& t : out.tracks) ...   // id, state, ellipse, position, velocity
//     if (out.grasp.valid) ...                     // out.grasp.plan: pre-grasp and grasp poses
//   }
//
// `ellipsekit track` runs exactly this path. Per frame: the detector's ellipses (all of them: the
// library keeps one per top), the image tracker (tracker.h), for each track hit this frame its 3-D
// top centre in the camera frame (the rim plane by default, rim_centre.h, given the track's predicted
// centre so that a taller object passing in front is not taken for the rim; the interior median for
// flat discs; the circle pose from `top_radius_m` when there is no depth or the depth fails),
// mapped to the output frame and smoothed by a constant-velocity Kalman filter per track. With a
// conveyor, the first confirmed track near the guide's image segment rides it: its top centre's
// pixel feeds the ConveyorTracker (speed, paper sec. V-B) and the grasp planner (grasp.h).
//
// The hot-path contract (as detect()'s): after the first frame, ProcessFrame() allocates nothing
// (tests/test_robot_no_allocation.cc counts), throws nothing, and its work is bounded by the
// detector's caps, the number of tracks and the rim samples' cap (RimSampleOptions::max_angles).
// Every buffer (detector, tracker, rim and interior samples, per-track filters, the conveyor's
// window, the caller's FrameOutput) is kept between frames, with room for 64 tracks and 256
// detections from the start; only a frame bringing more than any before makes one grow, once.
// Ordinary misses (a top without enough depth, a conveyor without a speed yet) build no message.
// A bad input (size, stamp, depth view) returns an error status naming it and leaves the loop as
// it was before the frame where possible.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "ellipsekit/detector.h"
#include "ellipsekit/robot/camera_model.h"
#include "ellipsekit/robot/conveyor.h"
#include "ellipsekit/robot/depth_sampling.h"
#include "ellipsekit/robot/grasp.h"
#include "ellipsekit/robot/kalman.h"
#include "ellipsekit/robot/rim_centre.h"
#include "ellipsekit/robot/tracker.h"

namespace ellipsekit::robot {

struct FrameLoopOptions {
  Options detector;                       // detector options (ellipsekit/options.h)
  TrackerOptions tracker;
  TopCentreMethod top_centre = TopCentreMethod::kRimPlane;
  RimSampleOptions rim;                   // plane_normal is set to the table normal (up_world)
  DepthSampleOptions interior;            // kInteriorMedian; plane_normal likewise
  double top_radius_m = 0;                // > 0: circle pose when depth is missing or fails
  Eigen::Matrix4d T_world_camera = Eigen::Matrix4d::Identity();  // output = T * camera
  Eigen::Vector3d up_world{0, 0, 1};      // the table normal, output frame
  std::optional<std::array<ConveyorReference, 2>> conveyor;  // references in the output frame
  ConveyorOptions conveyor_options;
  GraspOptions grasp;                     // latency_s: planning to pre-grasp
  // 3-D track filter: initial position variance (m^2), velocity variance ((m/s)^2), acceleration
  // density (m^2/s^3), measurement variance (m^2).
  double kf_position_var = 1e-6, kf_velocity_var = 0.04, kf_accel_density = 0.05, kf_measurement_var = 4e-6;
};

enum class CentreSource { kNone, kRimPlane, kInteriorMedian, kCirclePose, kPredicted };

const char* CentreSourceName(CentreSource s);

struct TrackOutput {
  std::int64_t id = 0;
  TrackState state = TrackState::kTentative;
  Ellipse ellipse;                     // the image track (filtered centre, smoothed axes)
  bool detected = false;               // hit this frame
  bool has_position = false;           // a 3-D position exists (measured now or before)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // output frame: this frame's measured top
                                                       // centre, or the filter's prediction when missed
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // filter velocity; the guide's speed on the belt
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // of this frame's measurement (output frame)
  CentreSource source = CentreSource::kNone;
  int samples = 0;                     // depth samples used (rim inliers or interior valid pixels)
  Eigen::Vector2d centre_pixel = Eigen::Vector2d::Zero();  // the 3-D centre projected (raw pixels)
  bool on_conveyor = false;
};

struct GraspOutput {
  bool valid = false;                  // a grasp now (decision kGrasp)
  std::int64_t track_id = -1;
  double target_time_s = 0;            // now + latency
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  // top centre predicted at target_time_s
  GraspPlan plan;                      // decision, pre-grasp and grasp poses, speed
};

struct FrameOutput {
  double stamp_s = 0;
  std::vector<Ellipse> detections;     // this frame's detector output
  std::vector<TrackOutput> tracks;     // every live track (tentative, confirmed, lost)
  GraspOutput grasp;
  std::int64_t conveyor_track_id = -1;
};

class FrameLoop {
 public:
  // `camera` describes the frames' raw pixels (and the registered depth images).
  FrameLoop(const CameraModel& camera, FrameLoopOptions options);
  // Not ok when the options or the camera are unusable (names the problem); every call then fails.
  Status status() const { return status_; }
  const FrameLoopOptions& options() const { return options_; }

  // One frame: 8-bit gray image, optional registered depth (nullptr: none), time in seconds
  // (increasing). The image must have the camera's size when the camera gives one.
  Status ProcessFrame(const ImageView& gray, const DepthImageView* depth, double stamp_s, FrameOutput* out);
  // The same from ellipses found by another detector (raw pixels).
  Status ProcessDetections(const std::vector<Ellipse>& detections, const DepthImageView* depth, double stamp_s,
                           FrameOutput* out);

  const EllipseTracker& tracker() const { return tracker_; }
  const std::optional<ConveyorTracker>& conveyor() const { return belt_; }
  // Output-frame point -> raw pixel (fails behind the camera).
  Result<Eigen::Vector2d> ProjectWorld(const Eigen::Vector3d& p) const;

 private:
  struct Track3D {
    std::int64_t id = 0;
    std::optional<ConstantVelocityKalman> kf;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    bool has_position = false;
    double last_t = 0;
  };
  Track3D* State(std::int64_t id);

  CameraModel camera_;
  FrameLoopOptions options_;
  Status status_;
  Detector detector_;
  DetectionResult result_;
  EllipseTracker tracker_;
  RimCentreSampler rim_;
  std::optional<ConveyorTracker> belt_;
  std::int64_t belt_id_ = -1;
  Eigen::Matrix3d R_wc_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t_wc_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d up_cam_ = Eigen::Vector3d::UnitZ();
  std::vector<Track3D> states_;
  std::vector<double> interior_depths_;  // TrySampleTopCentre's scratch
};

}  // namespace ellipsekit::robot
