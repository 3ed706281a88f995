// Position and speed along a linear guide from image observations (see conveyor.h).
#include "ellipsekit/robot/conveyor.h"

#include <cmath>

namespace ellipsekit::robot {

Result<ConveyorTracker> ConveyorTracker::Create(const ConveyorReference& start, const ConveyorReference& end,
                                                std::string frame_id, ConveyorOptions options) {
  using R = Result<ConveyorTracker>;
  if (!start.point.allFinite() || !end.point.allFinite() || !start.pixel.allFinite() || !end.pixel.allFinite()) {
    return R::Error(StatusCode::kInvalidArgument, "conveyor: non-finite reference");
  }
  const double len = (end.point - start.point).norm();
  if (!(len > 1e-6)) return R::Error(StatusCode::kInvalidArgument, "conveyor: reference points coincide");
  if (!((end.pixel - start.pixel).norm() > 1e-6)) {
    return R::Error(StatusCode::kInvalidArgument, "conveyor: reference pixels coincide");
  }
  if (start.camera_depth_z < 0 || end.camera_depth_z < 0 || !std::isfinite(start.camera_depth_z) ||
      !std::isfinite(end.camera_depth_z)) {
    return R::Error(StatusCode::kInvalidArgument, "conveyor: reference depths must be >= 0");
  }
  if (options.min_samples < 2 || !(options.window_s > 0)) {
    return R::Error(StatusCode::kInvalidArgument, "conveyor: min_samples >= 2 and window_s > 0 needed");
  }
  ConveyorTracker c;
  c.start_ = start;
  c.end_ = end;
  c.frame_id_ = std::move(frame_id);
  c.options_ = options;
  c.length_ = len;
  c.direction_ = (end.point - start.point) / len;
  c.samples_.reserve(256);
  c.pending_.reserve(256);
  return R::Ok(std::move(c));
}

double ConveyorTracker::PixelToPosition(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d d = end_.pixel - start_.pixel;
  const double t = (pixel - start_.pixel).dot(d) / d.squaredNorm();
  const double z0 = start_.camera_depth_z, z1 = end_.camera_depth_z;
  if (z0 > 0 && z1 > 0) {
    const double den = t * z0 + (1 - t) * z1;
    if (std::abs(den) > 1e-12) return length_ * t * z0 / den;
  }
  return length_ * t;
}

Eigen::Vector3d ConveyorTracker::PositionToPoint(double s) const { return start_.point + s * direction_; }

bool ConveyorTracker::Fit(double* s0, double* v, double* t_ref, double* rms) const {
  const std::size_t n = samples_.size();
  if (n < 2) return false;
  double tm = 0, sm = 0;
  for (const Sample& x : samples_) {
    tm += x.t;
    sm += x.s;
  }
  tm /= static_cast<double>(n);
  sm /= static_cast<double>(n);
  double stt = 0, sts = 0;
  for (const Sample& x : samples_) {
    stt += (x.t - tm) * (x.t - tm);
    sts += (x.t - tm) * (x.s - sm);
  }
  if (!(stt > 0)) return false;
  *v = sts / stt;
  *s0 = sm;
  *t_ref = tm;
  double r2 = 0;
  for (const Sample& x : samples_) {
    const double r = x.s - (sm + *v * (x.t - tm));
    r2 += r * r;
  }
  *rms = std::sqrt(r2 / static_cast<double>(n));
  return true;
}

Status ConveyorTracker::AddObservation(const Eigen::Vector2d& pixel, double stamp_s) {
  if (!pixel.allFinite() || !std::isfinite(stamp_s)) {
    return Status(StatusCode::kInvalidArgument, "conveyor: non-finite observation");
  }
  const double newest = !pending_.empty() ? pending_.back().t : (!samples_.empty() ? samples_.back().t : -INFINITY);
  if (!(stamp_s > newest)) return Status(StatusCode::kInvalidArgument, "conveyor: timestamps must increase");
  const Sample x{stamp_s, PixelToPosition(pixel)};

  double s0, v, tr, rms;
  if (static_cast<int>(samples_.size()) >= options_.min_samples && Fit(&s0, &v, &tr, &rms) &&
      std::abs(x.s - (s0 + v * (x.t - tr))) > options_.reversal_residual_m) {
    pending_.push_back(x);
    if (++misfits_ >= options_.reversal_count) {  // the motion changed: restart from the misfits
      samples_ = pending_;
      pending_.clear();
      misfits_ = 0;
    }
    return Status::Ok();
  }
  pending_.clear();
  misfits_ = 0;
  samples_.push_back(x);
  std::size_t drop = 0;  // the oldest samples out of the window, keeping at least 2
  while (samples_.size() - drop > 2 && samples_[drop].t < stamp_s - options_.window_s) ++drop;
  samples_.erase(samples_.begin(), samples_.begin() + static_cast<std::ptrdiff_t>(drop));
  return Status::Ok();
}

bool ConveyorTracker::HasSpeed() const {
  double s0, v, tr, rms;
  return static_cast<int>(samples_.size()) >= options_.min_samples && Fit(&s0, &v, &tr, &rms);
}

Result<ConveyorState> ConveyorTracker::State() const {
  using R = Result<ConveyorState>;
  double s0, v, tr, rms;
  if (static_cast<int>(samples_.size()) < options_.min_samples || !Fit(&s0, &v, &tr, &rms)) {
    return R::Error(StatusCode::kUnavailable, "conveyor: not enough observations for a speed");
  }
  ConveyorState st;
  st.stamp_s = samples_.back().t;
  st.position_m = s0 + v * (st.stamp_s - tr);
  st.speed_m_s = v;
  st.residual_rms_m = rms;
  st.samples = static_cast<int>(samples_.size());
  return R::Ok(st);
}

Result<double> ConveyorTracker::PredictPosition(double stamp_s) const {
  auto st = State();
  if (!st.ok()) return Result<double>{st.status, 0};
  return Result<double>::Ok(st.value.position_m + st.value.speed_m_s * (stamp_s - st.value.stamp_s));
}

}  // namespace ellipsekit::robot
