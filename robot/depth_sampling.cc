// Robust 3-D top centre from a registered depth image, and averaging (see depth_sampling.h).
#include "ellipsekit/robot/depth_sampling.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <Eigen/Dense>

#include "ellipsekit/robot/circle_pose.h"

namespace ellipsekit::robot {

namespace {

double Median(std::vector<double>& v) {
  const std::size_t n = v.size();
  const std::size_t mid = n / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  double m = v[mid];
  if (n % 2 == 0) {
    const double lower = *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid));
    m = 0.5 * (m + lower);
  }
  return m;
}

Status CheckView(const DepthImageView& d) {
  const std::size_t bpp = d.encoding == DepthEncoding::k16UC1 ? 2 : 4;
  if (d.data == nullptr || d.width <= 0 || d.height <= 0 ||
      d.step < static_cast<std::size_t>(d.width) * bpp) {
    return Status(StatusCode::kInvalidArgument, "depth: empty image or step < width * bytes per pixel");
  }
  return Status::Ok();
}

}  // namespace

double DepthAt(const DepthImageView& d, int x, int y) {
  const auto* row = static_cast<const std::uint8_t*>(d.data) + static_cast<std::size_t>(y) * d.step;
  if (d.encoding == DepthEncoding::k16UC1) {
    std::uint16_t mm;
    std::memcpy(&mm, row + 2 * static_cast<std::size_t>(x), 2);
    return mm == 0 ? std::numeric_limits<double>::quiet_NaN() : 0.001 * mm;
  }
  float m;
  std::memcpy(&m, row + 4 * static_cast<std::size_t>(x), 4);
  return (std::isfinite(m) && m > 0) ? static_cast<double>(m) : std::numeric_limits<double>::quiet_NaN();
}

namespace {

// SampleTopCentre into `z` (cleared, then one valid depth per pixel) and *result; on failure false,
// with the message in *err when err is not null (no message is built otherwise).
bool SampleInto(const Ellipse& e, const DepthImageView& depth, const CameraModel& camera,
                const DepthSampleOptions& opt, std::vector<double>& z, DepthSample* result, Status* err) {
  auto fail = [&](auto&& make) {
    if (err != nullptr) *err = make();
    return false;
  };
  if (Status s = CheckView(depth); !s.ok()) return fail([&] { return s; });
  if (!(std::isfinite(e.cx) && std::isfinite(e.cy) && std::isfinite(e.theta) && e.a > 0 && e.b > 0 &&
        std::isfinite(e.a) && std::isfinite(e.b))) {
    return fail([] { return Status(StatusCode::kInvalidArgument, "depth: degenerate ellipse"); });
  }
  if (!(opt.inner_scale > 0 && opt.inner_scale <= 1)) {
    return fail([] { return Status(StatusCode::kInvalidArgument, "depth: inner_scale must be in (0, 1]"); });
  }
  const double a = opt.inner_scale * e.a, b = opt.inner_scale * e.b;
  const double c = std::cos(e.theta), s = std::sin(e.theta);
  const double hx = std::sqrt(a * a * c * c + b * b * s * s), hy = std::sqrt(a * a * s * s + b * b * c * c);
  const int x0 = std::max(0, static_cast<int>(std::ceil(e.cx - hx)));
  const int x1 = std::min(depth.width - 1, static_cast<int>(std::floor(e.cx + hx)));
  const int y0 = std::max(0, static_cast<int>(std::ceil(e.cy - hy)));
  const int y1 = std::min(depth.height - 1, static_cast<int>(std::floor(e.cy + hy)));
  z.clear();
  int total = 0;
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const double dx = x - e.cx, dy = y - e.cy;
      const double u = (c * dx + s * dy) / a, v = (-s * dx + c * dy) / b;
      if (u * u + v * v > 1) continue;
      ++total;
      const double d = DepthAt(depth, x, y);
      if (std::isfinite(d) && d >= opt.min_depth_m && d <= opt.max_depth_m) z.push_back(d);
    }
  }
  const int valid = static_cast<int>(z.size());
  if (total == 0 || valid < opt.min_valid_samples ||
      valid < opt.min_valid_fraction * static_cast<double>(total)) {
    return fail([&] {
      return Status(StatusCode::kInvalidArgument, "depth: too few valid samples inside the ellipse (" +
                                                      std::to_string(valid) + " of " + std::to_string(total) + ")");
    });
  }
  DepthSample out;
  out.valid_samples = valid;
  out.total_samples = total;
  out.median_depth_m = Median(z);
  for (double& v : z) v = std::abs(v - out.median_depth_m);
  out.mad_depth_m = Median(z);

  const Eigen::Vector2d ne = camera.UndistortPixel(Eigen::Vector2d(e.cx, e.cy));
  const Eigen::Vector3d pe = Eigen::Vector3d(ne.x(), ne.y(), 1) * out.median_depth_m;
  out.centre = pe;
  if (opt.plane_normal) {
    auto cp = ProjectedCircleCentre(e, camera, *opt.plane_normal);
    if (!cp.ok()) return fail([&] { return cp.status; });
    const Eigen::Vector3d n = opt.plane_normal->normalized();
    const Eigen::Vector2d nc = camera.UndistortPixel(cp.value);
    const Eigen::Vector3d rc(nc.x(), nc.y(), 1);
    const double den = n.dot(rc);
    if (std::abs(den) > 1e-9) out.centre = rc * (n.dot(pe) / den);  // ray meets the top's plane
  }
  *result = out;
  return true;
}

}  // namespace

Result<DepthSample> SampleTopCentre(const Ellipse& e, const DepthImageView& depth, const CameraModel& camera,
                                    const DepthSampleOptions& opt) {
  std::vector<double> z;
  DepthSample out;
  Status err;
  if (SampleInto(e, depth, camera, opt, z, &out, &err)) return Result<DepthSample>::Ok(out);
  return Result<DepthSample>{err, {}};
}

bool TrySampleTopCentre(const Ellipse& e, const DepthImageView& depth, const CameraModel& camera,
                        const DepthSampleOptions& opt, std::vector<double>* scratch, DepthSample* out) {
  return scratch != nullptr && out != nullptr && SampleInto(e, depth, camera, opt, *scratch, out, nullptr);
}

void CentreAverager::Add(const Eigen::Vector3d& centre) {
  if (!centre.allFinite()) return;
  samples_.push_back(centre);
  if (options_.max_samples > 0 && samples_.size() > options_.max_samples) samples_.erase(samples_.begin());
}

Result<AveragedPoint> CentreAverager::Estimate() const {
  using R = Result<AveragedPoint>;
  if (samples_.empty()) return R::Error(StatusCode::kInvalidArgument, "averager: no samples");
  std::vector<double> tmp(samples_.size());
  Eigen::Vector3d med;
  for (int k = 0; k < 3; ++k) {
    for (std::size_t i = 0; i < samples_.size(); ++i) tmp[i] = samples_[i](k);
    med(k) = Median(tmp);
  }
  std::vector<double> dist(samples_.size());
  for (std::size_t i = 0; i < samples_.size(); ++i) dist[i] = (samples_[i] - med).norm();
  tmp = dist;
  const double gate = std::max(options_.outlier_k * 1.4826 * Median(tmp), options_.min_gate_m);
  AveragedPoint out;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < samples_.size(); ++i) {
    if (dist[i] <= gate) {
      sum += samples_[i];
      ++out.inliers;
    } else {
      ++out.outliers;
    }
  }
  out.mean = sum / out.inliers;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < samples_.size(); ++i) {
    if (dist[i] <= gate) {
      const Eigen::Vector3d d = samples_[i] - out.mean;
      cov += d * d.transpose();
    }
  }
  out.sample_covariance = out.inliers > 1 ? Eigen::Matrix3d(cov / (out.inliers - 1)) : Eigen::Matrix3d::Zero();
  out.covariance = out.sample_covariance / out.inliers;
  return R::Ok(out);
}

Result<PointWithCovarianceStamped> CentreAverager::EstimateStamped(const Header& header) const {
  using R = Result<PointWithCovarianceStamped>;
  auto e = Estimate();
  if (!e.ok()) return R{e.status, {}};
  PointWithCovarianceStamped m;
  m.header = header;
  m.point = Point{e.value.mean.x(), e.value.mean.y(), e.value.mean.z()};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m.covariance[static_cast<std::size_t>(3 * r + c)] = e.value.covariance(r, c);
  return R::Ok(m);
}

}  // namespace ellipsekit::robot
