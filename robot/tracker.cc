// Multi-object ellipse tracker: gating, Hungarian assignment, constant-velocity Kalman filters.
#include "ellipsekit/robot/tracker.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "ellipsekit/robot/hungarian.h"

namespace ellipsekit::robot {

namespace {

// Whether the point (x, y) lies inside the ellipse (cx, cy, a, b, theta).
bool Inside(double x, double y, double cx, double cy, double a, double b, double theta) {
  const double dx = x - cx, dy = y - cy, c = std::cos(theta), s = std::sin(theta);
  const double u = (c * dx + s * dy) / a, v = (-s * dx + c * dy) / b;
  return u * u + v * v <= 1.0;
}

}  // namespace

const char* TrackStateName(TrackState s) {
  switch (s) {
    case TrackState::kTentative: return "tentative";
    case TrackState::kConfirmed: return "confirmed";
    case TrackState::kLost: return "lost";
  }
  return "?";
}

EllipseTracker::EllipseTracker(TrackerOptions options) : options_(options) {
  tracks_.reserve(kTracksRoom);
  filters_.reserve(kTracksRoom);
  cost_.reserve(static_cast<std::size_t>(kTracksRoom) * kDetectionsRoom);
  det_used_.reserve(kDetectionsRoom);
  solver_.Reserve(kTracksRoom, kDetectionsRoom);
}

void EllipseTracker::Reset() {
  tracks_.clear();
  filters_.clear();
  next_id_ = 1;
  has_stamp_ = false;
}

const Track* EllipseTracker::Find(std::int64_t id) const {
  for (const Track& t : tracks_)
    if (t.id == id) return &t;
  return nullptr;
}

std::vector<Track> EllipseTracker::ConfirmedTracks() const {
  std::vector<Track> out;
  for (const Track& t : tracks_)
    if (t.state != TrackState::kTentative) out.push_back(t);
  return out;
}

Status EllipseTracker::Update(const std::vector<Ellipse>& dets, double stamp_s) {
  if (!std::isfinite(stamp_s) || (has_stamp_ && !(stamp_s > last_stamp_))) {
    return Status(StatusCode::kInvalidArgument, "tracker: timestamps must increase");
  }
  for (const Ellipse& e : dets) {
    if (!(std::isfinite(e.cx) && std::isfinite(e.cy) && std::isfinite(e.a) && std::isfinite(e.b) && e.a > 0 &&
          e.b > 0)) {
      return Status(StatusCode::kInvalidArgument, "tracker: degenerate detection");
    }
  }
  const double dt = has_stamp_ ? stamp_s - last_stamp_ : 0.0;
  last_stamp_ = stamp_s;
  has_stamp_ = true;

  for (auto& f : filters_) f.kf.Predict(dt);

  // Gated cost matrix: tracks x detections (column-major, in the kept buffer).
  const double kForbidden = 1e18;
  const int nt = static_cast<int>(tracks_.size()), nd = static_cast<int>(dets.size());
  cost_.resize(static_cast<std::size_t>(nt) * static_cast<std::size_t>(nd));
  for (int i = 0; i < nt; ++i) {
    const auto& f = filters_[static_cast<std::size_t>(i)];
    const Eigen::Vector2d pred = f.kf.position();
    const Eigen::Matrix2d S = f.kf.PositionCovariance() + options_.measurement_var * Eigen::Matrix2d::Identity();
    // Largest eigenvalue of the symmetric 2 x 2 S.
    const double half_tr = 0.5 * (S(0, 0) + S(1, 1));
    const double lmax = half_tr + std::sqrt(0.25 * (S(0, 0) - S(1, 1)) * (S(0, 0) - S(1, 1)) + S(0, 1) * S(1, 0));
    const double sigma = std::sqrt(lmax);
    const double gate = std::min(std::max(options_.gate_px, options_.gate_sigmas * sigma), 4 * options_.gate_px);
    for (int j = 0; j < nd; ++j) {
      const Ellipse& d = dets[static_cast<std::size_t>(j)];
      const double dist = (Eigen::Vector2d(d.cx, d.cy) - pred).norm();
      const double axis = std::max(std::abs(d.a - f.a) / f.a, std::abs(d.b - f.b) / f.b);
      cost_[static_cast<std::size_t>(i) + static_cast<std::size_t>(j) * static_cast<std::size_t>(nt)] =
          (dist > gate || axis > options_.max_axis_rel_diff) ? kForbidden
                                                             : dist / gate + options_.axis_cost_weight * axis;
    }
  }
  const std::vector<int>& match = solver_.Solve(cost_.data(), nt, nd, kForbidden);

  det_used_.assign(static_cast<std::size_t>(nd), 0);
  int kept = 0;  // tracks are compacted in place: kept ones move to the front, in order
  for (int i = 0; i < nt; ++i) {
    Track& t = tracks_[static_cast<std::size_t>(i)];
    auto& f = filters_[static_cast<std::size_t>(i)];
    const int j = match[static_cast<std::size_t>(i)];
    bool keep = true;
    t.detection_index = j;
    if (j >= 0) {
      const Ellipse& d = dets[static_cast<std::size_t>(j)];
      det_used_[static_cast<std::size_t>(j)] = 1;
      f.kf.Update(Eigen::Vector2d(d.cx, d.cy));
      const double w = options_.axis_smoothing;
      f.a = (1 - w) * f.a + w * d.a;
      f.b = (1 - w) * f.b + w * d.b;
      f.score = (1 - w) * f.score + w * d.score;
      t.ellipse.theta = d.theta;
      t.ellipse.score = d.score;
      ++t.hits;
      t.misses = 0;
      t.last_seen_s = stamp_s;
      if (t.state == TrackState::kLost || (t.state == TrackState::kTentative && t.hits >= options_.confirm_hits)) {
        t.state = TrackState::kConfirmed;
      }
    } else {
      ++t.misses;
      if (t.state == TrackState::kTentative) {
        keep = false;
      } else {
        t.state = TrackState::kLost;
        if (stamp_s - t.last_seen_s > options_.max_lost_s) keep = false;
      }
    }
    const Eigen::Vector2d p = f.kf.position();
    t.ellipse.cx = p.x();
    t.ellipse.cy = p.y();
    t.ellipse.a = std::max(f.a, f.b);
    t.ellipse.b = std::min(f.a, f.b);
    t.velocity_px_s = f.kf.velocity();
    if (keep) {
      if (kept != i) {
        tracks_[static_cast<std::size_t>(kept)] = t;
        filters_[static_cast<std::size_t>(kept)] = f;
      }
      ++kept;
    }
  }
  tracks_.erase(tracks_.begin() + kept, tracks_.end());
  filters_.erase(filters_.begin() + kept, filters_.end());
  // Track birth. A detection left unassigned that overlaps an established (confirmed or lost)
  // track, i.e. its centre lies inside the track's ellipse at the filtered/predicted position or the
  // track's centre inside the detection, competes with that track for the same image region: two
  // can tops cannot overlap that much while both are seen whole. Such detections are mostly a second
  // contour of the object (body, shadow, rim) or an ellipse merging the tops of crossing objects;
  // they recur for a few frames, and a track born on them gets confirmed while the object's own
  // track is missed, then holds the object's detections or its id. So:
  //   - a detection overlapping two or more established tracks is a merge of their tops: no birth;
  //   - a detection overlapping one established track starts a track only when it is better
  //     supported by the image (detector score) than the detections that track was built on, so an
  //     established track keeps its area against weaker artefacts, but a track that was itself
  //     confirmed on an artefact does not block the real top from getting its own track.
  auto may_start_track = [&](const Ellipse& d) {
    int overlapped = 0;
    double best_score = -INFINITY;
    for (std::size_t i = 0; i < tracks_.size(); ++i) {
      if (tracks_[i].state == TrackState::kTentative) continue;
      const Internal& f = filters_[i];
      const Eigen::Vector2d p = f.kf.position();
      if (Inside(d.cx, d.cy, p.x(), p.y(), f.a, f.b, tracks_[i].ellipse.theta) ||
          Inside(p.x(), p.y(), d.cx, d.cy, d.a, d.b, d.theta)) {
        ++overlapped;
        best_score = std::max(best_score, f.score);
      }
    }
    return overlapped == 0 || (overlapped == 1 && d.score > best_score);
  };
  for (int j = 0; j < nd; ++j) {
    if (det_used_[static_cast<std::size_t>(j)] || !may_start_track(dets[static_cast<std::size_t>(j)])) continue;
    Track t;
    t.id = next_id_++;
    t.state = options_.confirm_hits <= 1 ? TrackState::kConfirmed : TrackState::kTentative;
    t.ellipse = dets[j];
    t.hits = 1;
    t.first_seen_s = t.last_seen_s = stamp_s;
    t.detection_index = j;
    tracks_.push_back(t);
    filters_.push_back(Internal{ConstantVelocityKalman(Eigen::Vector2d(dets[j].cx, dets[j].cy),
                                                      options_.measurement_var, options_.initial_velocity_var,
                                                      options_.accel_density, options_.measurement_var),
                               dets[j].a, dets[j].b, dets[j].score});
  }
  return Status::Ok();
}

}  // namespace ellipsekit::robot
