// 3-D centre of a detected top from a registered depth image, and averaging over detections.
//
// Sampling: every pixel inside the ellipse shrunk by `inner_scale` (to stay off the rim, where
// depth jumps to the can's side or the table) is read; invalid samples are skipped (0 in 16UC1,
// NaN/inf/<=0 in 32FC1). The median depth z of the valid samples is taken. For a plane, 1/z is
// affine in the pixel, so over a centrally symmetric region the median z is exactly the plane's
// depth at the region's centre: the point is ray(ellipse centre) scaled to that z. If the plane
// normal is known, that point is moved along the plane to the ray through the true projected
// circle centre (the pole of the vanishing line), which removes the perspective offset.
//
// Averaging (the paper averages 20 detections): per-axis medians, distances to that median,
// inliers within max(k * 1.4826 * MAD, min_gate) — then mean and covariance of the inliers.
//
// Frames: camera optical frame, metres.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "ellipsekit/robot/camera_model.h"
#include "ellipsekit/robot/messages.h"
#include "ellipsekit/types.h"

namespace ellipsekit::robot {

struct DepthSampleOptions {
  double inner_scale = 0.7;       // sample inside (inner_scale * a, inner_scale * b)
  int min_valid_samples = 5;      // fewer valid samples -> error
  double min_valid_fraction = 0.2;  // of the pixels inside the region
  double min_depth_m = 0.1;       // plausible range; samples outside count as invalid
  double max_depth_m = 10.0;
  std::optional<Eigen::Vector3d> plane_normal;  // camera frame; enables the centre correction
};

struct DepthSample {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // camera frame, metres
  double median_depth_m = 0;   // median z of the valid samples
  double mad_depth_m = 0;      // median absolute deviation of z
  int valid_samples = 0;
  int total_samples = 0;
};

// Reads one depth value in metres; NaN when invalid. (x, y) must be inside the image.
double DepthAt(const DepthImageView& depth, int x, int y);

// The 3-D top centre of one detection. The ellipse is in raw pixels of `camera`, and the depth
// image is registered to it. Fails on a bad view, a degenerate ellipse, or too few valid samples.
Result<DepthSample> SampleTopCentre(const Ellipse& ellipse, const DepthImageView& depth,
                                    const CameraModel& camera, const DepthSampleOptions& options = {});
// The same for a loop: the depths go to `scratch`, which keeps its room between calls (reserve it
// for the largest region, e.g. the image's pixel count, and it never grows); false on any failure,
// without building a message (SampleTopCentre says why).
bool TrySampleTopCentre(const Ellipse& ellipse, const DepthImageView& depth, const CameraModel& camera,
                        const DepthSampleOptions& options, std::vector<double>* scratch, DepthSample* out);

struct AveragerOptions {
  double outlier_k = 3.0;          // inlier gate in robust sigmas (1.4826 MAD)
  double min_gate_m = 0.003;       // the gate never falls below this (metres)
  std::size_t max_samples = 20;    // keep the newest N (the paper's 20); 0 = unbounded
};

struct AveragedPoint {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();            // metres
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();      // of the mean, m^2 (sample cov / n)
  Eigen::Matrix3d sample_covariance = Eigen::Matrix3d::Zero();  // spread of single samples, m^2
  int inliers = 0;
  int outliers = 0;
};

// Accumulates per-detection centres of one object and returns a robust average.
class CentreAverager {
 public:
  explicit CentreAverager(AveragerOptions options = {}) : options_(options) {}
  void Add(const Eigen::Vector3d& centre);
  void Clear() { samples_.clear(); }
  std::size_t size() const { return samples_.size(); }
  // Fails when empty.
  Result<AveragedPoint> Estimate() const;
  // The estimate as a stamped message (covariance of the mean, row-major).
  Result<PointWithCovarianceStamped> EstimateStamped(const Header& header) const;

 private:
  AveragerOptions options_;
  std::vector<Eigen::Vector3d> samples_;
};

}  // namespace ellipsekit::robot
