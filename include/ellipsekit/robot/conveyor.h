// Position and speed of an object riding a linear guide, from its image only (paper sec. V-B).
//
// Calibration, once: the object's top centre is recorded at both ends of the guide as a 3-D point
// in the output frame (e.g. the robot base, metres) together with its pixel (the ellipse centre,
// or the projected circle centre — use the same kind later). Then a pixel maps to a position s
// (metres from the start reference, along the guide) by projecting it onto the image segment
// between the two reference pixels: t in [0, 1] at the references. The paper interpolates
// linearly (s = t L). Perspective makes that mapping projective; if the references' depths in
// the camera frame (z0, z1) are given, the exact one is used: s = L t z0 / (t z0 + (1 - t) z1).
//
// Speed: least-squares line s(t) over the newest window of observations. When the object turns
// round (the guide's return phase), new samples stop fitting; after `reversal_count` consecutive
// misfits the window restarts from them.
//
// The observations live in vectors that keep their room (256 from the start; more only when a
// window holds more observations than that): AddObservation, HasSpeed and State do not allocate.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "ellipsekit/robot/messages.h"

namespace ellipsekit::robot {

struct ConveyorReference {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // top centre at this end, output frame, m
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  // its image, raw pixels
  double camera_depth_z = 0;  // its z in the camera optical frame (m); 0 = unknown (linear mapping)
};

struct ConveyorOptions {
  double window_s = 1.0;            // regression window (seconds of the newest observations)
  int min_samples = 6;              // fewer -> no speed yet
  double reversal_residual_m = 0.006;  // a sample this far off the fitted line is a misfit
  int reversal_count = 3;           // consecutive misfits that restart the window
};

struct ConveyorState {
  double stamp_s = 0;      // newest observation time
  double position_m = 0;   // fitted position along the guide at stamp_s (from the start reference)
  double speed_m_s = 0;    // signed: > 0 moving from the start reference to the end one
  double residual_rms_m = 0;
  int samples = 0;
};

class ConveyorTracker {
 public:
  // Fails when the reference points or pixels coincide, or a depth is negative.
  static Result<ConveyorTracker> Create(const ConveyorReference& start, const ConveyorReference& end,
                                        std::string frame_id, ConveyorOptions options = {});

  double length_m() const { return length_; }
  const std::string& frame_id() const { return frame_id_; }
  // Unit direction of the guide (start -> end), output frame.
  Eigen::Vector3d direction() const { return direction_; }

  // Position along the guide (metres from start; may fall outside [0, length]).
  double PixelToPosition(const Eigen::Vector2d& pixel) const;
  // The 3-D point (output frame) at position s.
  Eigen::Vector3d PositionToPoint(double s) const;

  // One observation (pixel of the object's centre at stamp_s, seconds, increasing).
  Status AddObservation(const Eigen::Vector2d& pixel, double stamp_s);
  void Reset() {
    samples_.clear();
    pending_.clear();
    misfits_ = 0;
  }

  // Whether State() succeeds now (enough samples for a line), without building its error.
  bool HasSpeed() const;
  // The fitted state; fails with too few samples.
  Result<ConveyorState> State() const;
  // Position along the guide at time stamp_s (extrapolated along the fitted line).
  Result<double> PredictPosition(double stamp_s) const;

 private:
  struct Sample {
    double t, s;
  };
  bool Fit(double* s0, double* v, double* t_ref, double* rms) const;

  ConveyorReference start_, end_;
  std::string frame_id_;
  ConveyorOptions options_;
  double length_ = 0;
  Eigen::Vector3d direction_ = Eigen::Vector3d::UnitX();
  std::vector<Sample> samples_;  // oldest first
  std::vector<Sample> pending_;  // consecutive misfits
  int misfits_ = 0;
};

}  // namespace ellipsekit::robot
