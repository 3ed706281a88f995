// Multi-object ellipse tracker in the image: stable ids across frames.
//
// Each track runs a constant-velocity Kalman filter on the ellipse centre (pixels, driven by the
// frame timestamps) and smooths the semi-axes. A frame's detections are gated against every track
// by centre distance to the predicted centre (pixels, widened by the predicted uncertainty) and by
// axis similarity (relative difference of a and of b), then assigned optimally (Hungarian).
// Unassigned detections start tentative tracks, except where they overlap an established track
// (a merge of two tops, or a weaker second contour of one; see Update); a track is confirmed after `confirm_hits` hits,
// becomes lost when missed, and is deleted after `max_lost_s` without a hit (tentative: at once).
//
// Update() keeps its buffers (tracks, filters, the cost matrix, the assignment's) between frames:
// it allocates only when a frame brings more detections or tracks than it has room for (room for
// 64 tracks and 256 detections from the start), and then grows once.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "ellipsekit/robot/hungarian.h"
#include "ellipsekit/robot/kalman.h"
#include "ellipsekit/robot/messages.h"
#include "ellipsekit/types.h"

namespace ellipsekit::robot {

enum class TrackState { kTentative, kConfirmed, kLost };

const char* TrackStateName(TrackState s);

struct TrackerOptions {
  double gate_px = 30.0;              // centre gate (pixels) around the prediction
  double gate_sigmas = 4.0;           // the gate also widens to this many predicted sigmas
  double max_axis_rel_diff = 0.35;    // |a_det - a_trk| / a_trk and the same for b
  double axis_cost_weight = 1.0;      // cost = centre_dist / gate + weight * axis_rel_diff
  int confirm_hits = 3;               // hits to confirm
  double max_lost_s = 0.5;            // a confirmed track is deleted after this long unseen
  double accel_density = 2000.0;      // q, px^2 / s^3
  double measurement_var = 1.0;       // px^2
  double initial_velocity_var = 1e4;  // (px/s)^2
  double axis_smoothing = 0.3;        // weight of the newest axes (exponential smoothing)
};

struct Track {
  std::int64_t id = 0;
  TrackState state = TrackState::kTentative;
  Ellipse ellipse;                       // filtered centre, smoothed axes, latest theta and score
  Eigen::Vector2d velocity_px_s = Eigen::Vector2d::Zero();
  int hits = 0;
  int misses = 0;                        // consecutive frames without a hit
  double first_seen_s = 0;
  double last_seen_s = 0;
  int detection_index = -1;              // index into the last Update's detections, -1 if missed
};

class EllipseTracker {
 public:
  // The room Update() has from the start (see above); FrameLoop sizes its outputs alike.
  static constexpr int kTracksRoom = 64, kDetectionsRoom = 256;

  explicit EllipseTracker(TrackerOptions options = {});

  // One frame at time `stamp_s` (seconds, increasing). Returns an error for non-increasing time
  // or a degenerate detection (the frame is then ignored).
  Status Update(const std::vector<Ellipse>& detections, double stamp_s);

  const std::vector<Track>& tracks() const { return tracks_; }
  // Confirmed tracks (and lost ones still kept), for output.
  std::vector<Track> ConfirmedTracks() const;
  const Track* Find(std::int64_t id) const;
  void Reset();

 private:
  struct Internal {
    ConstantVelocityKalman kf;
    double a, b;
    double score;  // smoothed detector score of the track's detections (same weight as the axes)
  };
  TrackerOptions options_;
  std::vector<Track> tracks_;
  std::vector<Internal> filters_;
  std::vector<double> cost_;      // tracks x detections, column-major
  std::vector<char> det_used_;
  AssignmentSolver solver_;
  std::int64_t next_id_ = 1;
  double last_stamp_ = 0;
  bool has_stamp_ = false;
};

}  // namespace ellipsekit::robot
