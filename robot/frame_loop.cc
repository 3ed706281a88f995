// One call per frame for the robot loop (see frame_loop.h).
#include "ellipsekit/robot/frame_loop.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "ellipsekit/robot/circle_pose.h"

namespace ellipsekit::robot {

const char* CentreSourceName(CentreSource s) {
  switch (s) {
    case CentreSource::kNone: return "none";
    case CentreSource::kRimPlane: return "rim-plane";
    case CentreSource::kInteriorMedian: return "interior-median";
    case CentreSource::kCirclePose: return "circle-pose";
    case CentreSource::kPredicted: return "predicted";
  }
  return "?";
}

FrameLoop::FrameLoop(const CameraModel& camera, FrameLoopOptions options)
    : camera_(camera), options_(std::move(options)), detector_(options_.detector), tracker_(options_.tracker),
      rim_(options_.rim) {
  status_ = detector_.status();
  if (!status_.ok()) return;
  const Eigen::Matrix4d& T = options_.T_world_camera;
  R_wc_ = T.topLeftCorner<3, 3>();
  t_wc_ = T.topRightCorner<3, 1>();
  if (!T.allFinite() || (R_wc_.transpose() * R_wc_ - Eigen::Matrix3d::Identity()).norm() > 1e-3) {
    status_ = Status(StatusCode::kInvalidArgument, "frame loop: T_world_camera's rotation is not orthonormal");
    return;
  }
  if (!(options_.up_world.allFinite() && options_.up_world.norm() > 1e-9)) {
    status_ = Status(StatusCode::kInvalidArgument, "frame loop: up_world must be a finite non-zero vector");
    return;
  }
  if (!(options_.top_radius_m >= 0 && std::isfinite(options_.top_radius_m))) {
    status_ = Status(StatusCode::kInvalidArgument, "frame loop: top_radius_m must be >= 0");
    return;
  }
  up_cam_ = (R_wc_.transpose() * options_.up_world).normalized();
  rim_.mutable_options().plane_normal = up_cam_;
  options_.interior.plane_normal = up_cam_;
  if (options_.conveyor) {
    auto c = ConveyorTracker::Create((*options_.conveyor)[0], (*options_.conveyor)[1], "world",
                                     options_.conveyor_options);
    if (!c.ok()) {
      status_ = Status(StatusCode::kInvalidArgument, "frame loop: conveyor: " + c.status.message());
      return;
    }
    belt_ = std::move(c.value);
  }
  // Room for the tracks the tracker has room for (tracker.h), and for the interior median's depths
  // (at most the image's pixels): the per-frame work then allocates nothing.
  states_.reserve(EllipseTracker::kTracksRoom);
  if (options_.top_centre == TopCentreMethod::kInteriorMedian && camera_.width() > 0 && camera_.height() > 0)
    interior_depths_.reserve(static_cast<std::size_t>(camera_.width()) * static_cast<std::size_t>(camera_.height()));
}

Result<Eigen::Vector2d> FrameLoop::ProjectWorld(const Eigen::Vector3d& p) const {
  return camera_.Project(R_wc_.transpose() * (p - t_wc_));
}

FrameLoop::Track3D* FrameLoop::State(std::int64_t id) {
  for (Track3D& s : states_)
    if (s.id == id) return &s;
  states_.emplace_back();
  states_.back().id = id;
  return &states_.back();
}

Status FrameLoop::ProcessFrame(const ImageView& gray, const DepthImageView* depth, double stamp_s, FrameOutput* out) {
  if (!status_.ok()) return status_;
  if (out == nullptr) return Status(StatusCode::kInvalidArgument, "frame loop: null output");
  if ((camera_.width() > 0 && gray.width != camera_.width()) || (camera_.height() > 0 && gray.height != camera_.height()))
    return Status(StatusCode::kInvalidArgument, "frame loop: image size " + std::to_string(gray.width) + "x" +
                                                    std::to_string(gray.height) + " differs from the camera's " +
                                                    std::to_string(camera_.width()) + "x" +
                                                    std::to_string(camera_.height()));
  if (Status st = detector_.detect(gray, &result_); !st.ok()) return st;
  return ProcessDetections(result_.ellipses, depth, stamp_s, out);
}

Status FrameLoop::ProcessDetections(const std::vector<Ellipse>& dets, const DepthImageView* depth, double stamp_s,
                                    FrameOutput* out) {
  if (!status_.ok()) return status_;
  if (out == nullptr) return Status(StatusCode::kInvalidArgument, "frame loop: null output");
  if (depth != nullptr) {
    const std::size_t bpp = depth->encoding == DepthEncoding::k16UC1 ? 2 : 4;
    if (depth->data == nullptr || depth->width <= 0 || depth->height <= 0 ||
        depth->step < static_cast<std::size_t>(depth->width) * bpp)
      return Status(StatusCode::kInvalidArgument, "frame loop: depth: empty image or step < width * bytes per pixel");
    if ((camera_.width() > 0 && depth->width != camera_.width()) ||
        (camera_.height() > 0 && depth->height != camera_.height()))
      return Status(StatusCode::kInvalidArgument, "frame loop: depth size differs from the camera's");
  }
  if (Status st = tracker_.Update(dets, stamp_s); !st.ok()) return st;
  out->stamp_s = stamp_s;
  // The caller's output keeps its room (a vector's copy assignment reuses it); it gets the same room
  // as the tracker's on the first frame, so a frame with a few more tops does not grow it.
  constexpr std::size_t kDetectionsRoom = EllipseTracker::kDetectionsRoom, kTracksRoom = EllipseTracker::kTracksRoom;
  if (out->detections.capacity() < kDetectionsRoom) out->detections.reserve(kDetectionsRoom);
  if (out->tracks.capacity() < kTracksRoom) out->tracks.reserve(kTracksRoom);
  out->detections = dets;
  out->tracks.clear();
  out->grasp = GraspOutput();  // its frame ids are empty strings: no allocation

  // 3-D top centres of the tracks hit this frame.
  for (const Track& tr : tracker_.tracks()) {
    Track3D& s = *State(tr.id);
    if (s.kf) s.kf->Predict(stamp_s - s.last_t);
    s.last_t = stamp_s;
    TrackOutput to;
    to.id = tr.id;
    to.state = tr.state;
    to.ellipse = tr.ellipse;
    to.detected = tr.detection_index >= 0;
    if (to.detected) {
      const Ellipse& e = dets[static_cast<std::size_t>(tr.detection_index)];
      std::optional<Eigen::Vector3d> pc;
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      // The Try* calls: a failure (too little depth on this top) is ordinary here, and falls back
      // to the circle pose without building an error message.
      if (depth != nullptr && options_.top_centre == TopCentreMethod::kRimPlane) {
        RimSample rs;
        // The track's predicted centre tells an occluder's top in front of the rim from the rim.
        if (s.kf)
          rim_.mutable_options().expected_centre = R_wc_.transpose() * (Eigen::Vector3d(s.kf->position()) - t_wc_);
        else
          rim_.mutable_options().expected_centre.reset();
        if (rim_.TrySample(e, *depth, camera_, &rs)) {
          pc = rs.centre;
          cov = rs.covariance;
          to.samples = rs.inliers;
          to.source = CentreSource::kRimPlane;
        }
      } else if (depth != nullptr) {
        DepthSample ds;
        if (TrySampleTopCentre(e, *depth, camera_, options_.interior, &interior_depths_, &ds)) {
          pc = ds.centre;
          const double sz = 1.4826 * ds.mad_depth_m / std::sqrt(std::max(1, ds.valid_samples));
          const Eigen::Vector3d dir = pc->normalized();
          cov = dir * dir.transpose() * (sz * sz);
          to.samples = ds.valid_samples;
          to.source = CentreSource::kInteriorMedian;
        }
      }
      if (!pc && options_.top_radius_m > 0) {
        auto cp = CirclePoseByNormal(e, options_.top_radius_m, camera_, up_cam_);
        if (cp.ok()) {
          pc = cp.value.centre;
          to.source = CentreSource::kCirclePose;
        }
      }
      if (pc) {
        const Eigen::Vector3d pw = R_wc_ * *pc + t_wc_;
        s.position = pw;
        s.has_position = true;
        if (!s.kf) {
          s.kf.emplace(pw, options_.kf_position_var, options_.kf_velocity_var, options_.kf_accel_density,
                       options_.kf_measurement_var);
        } else {
          s.kf->Update(pw);
        }
        to.covariance = R_wc_ * cov * R_wc_.transpose();
        auto px = camera_.Project(*pc);
        if (px.ok()) to.centre_pixel = px.value;
      }
    } else if (s.kf) {
      to.source = CentreSource::kPredicted;
      auto px = ProjectWorld(s.kf->position());
      if (px.ok()) to.centre_pixel = px.value;
    }
    to.has_position = s.has_position;
    if (s.has_position) {
      to.position = to.detected && to.source != CentreSource::kNone ? s.position : Eigen::Vector3d(s.kf->position());
      to.velocity = s.kf->velocity();
    }
    out->tracks.push_back(to);
  }
  // Forget deleted tracks.
  states_.erase(std::remove_if(states_.begin(), states_.end(),
                               [&](const Track3D& s) { return tracker_.Find(s.id) == nullptr; }),
                states_.end());

  if (!belt_) return Status::Ok();
  // The conveyor: one track, the first confirmed one near the guide; observations of its centre.
  if (belt_id_ >= 0 && tracker_.Find(belt_id_) == nullptr) {
    belt_id_ = -1;
    belt_->Reset();
  }
  const Eigen::Vector2d a = (*options_.conveyor)[0].pixel, b = (*options_.conveyor)[1].pixel;
  if (belt_id_ < 0) {
    double best = 1e300;
    for (const TrackOutput& t : out->tracks) {
      if (t.state != TrackState::kConfirmed || !t.detected || t.source == CentreSource::kNone) continue;
      const Eigen::Vector2d p = t.centre_pixel;
      const double u = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), -0.2, 1.2);
      const double d = (p - (a + u * (b - a))).norm();
      if (d < std::max(20.0, 2 * t.ellipse.b) && d < best) {
        best = d;
        belt_id_ = t.id;
      }
    }
  }
  out->conveyor_track_id = belt_id_;
  for (TrackOutput& t : out->tracks) {
    if (t.id != belt_id_) continue;
    t.on_conveyor = true;
    if (t.detected && t.source != CentreSource::kNone) {
      if (Status st = belt_->AddObservation(t.centre_pixel, stamp_s); !st.ok()) return st;
    }
    if (belt_->HasSpeed()) {
      auto bs = belt_->State();
      if (bs.ok()) t.velocity = bs.value.speed_m_s * belt_->direction();
    }
  }
  if (belt_id_ >= 0 && belt_->HasSpeed()) {  // no speed yet: no plan (and no error message built)
    auto plan = PlanConveyorGrasp(*belt_, stamp_s, options_.grasp);
    auto s_then = belt_->PredictPosition(stamp_s + options_.grasp.latency_s);
    if (plan.ok() && s_then.ok()) {
      out->grasp.track_id = belt_id_;
      out->grasp.plan = plan.value;
      out->grasp.target_time_s = stamp_s + options_.grasp.latency_s;
      out->grasp.target = belt_->PositionToPoint(s_then.value);
      out->grasp.valid = plan.value.decision == GraspDecision::kGrasp;
    }
  }
  return Status::Ok();
}

}  // namespace ellipsekit::robot
