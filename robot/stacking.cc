// Region states of the stacking task (see stacking.h).
#include "ellipsekit/robot/stacking.h"

#include <set>

namespace ellipsekit::robot {

namespace {
double Side(const StackingRegions& r, const Eigen::Vector2d& p) {
  const Eigen::Vector2d d = r.line_p1 - r.line_p0, q = p - r.line_p0;
  return d.x() * q.y() - d.y() * q.x();
}
}  // namespace

bool StackingMonitor::OnFeedSide(const Eigen::Vector2d& pixel) const {
  return Side(regions_, pixel) * Side(regions_, regions_.feed_side_pixel) > 0;
}

std::vector<StackingEvent> StackingMonitor::Update(const std::vector<Track>& tracks, double stamp_s) {
  std::vector<StackingEvent> events;
  std::set<std::int64_t> seen;
  for (const Track& t : tracks) {
    if (t.state == TrackState::kTentative) continue;
    seen.insert(t.id);
    const bool feed = OnFeedSide(Eigen::Vector2d(t.ellipse.cx, t.ellipse.cy));
    const ObjectRole role = feed ? ObjectRole::kNew : ObjectRole::kStacked;
    auto it = objects_.find(t.id);
    if (it == objects_.end()) {
      objects_[t.id] = StackingObject{t.id, role, t.ellipse, stamp_s};
      events.push_back({role == ObjectRole::kNew ? StackingEvent::kNewObject : StackingEvent::kObjectStacked,
                        t.id, stamp_s});
    } else {
      it->second.ellipse = t.ellipse;
      if (it->second.role != role) {
        it->second.role = role;
        it->second.role_since_s = stamp_s;
        events.push_back({role == ObjectRole::kNew ? StackingEvent::kNewObject : StackingEvent::kObjectStacked,
                          t.id, stamp_s});
      }
    }
  }
  for (auto it = objects_.begin(); it != objects_.end();) {
    it = seen.count(it->first) ? std::next(it) : objects_.erase(it);
  }
  // Next target: the stacked object that became stacked last (ties: highest in the image).
  std::optional<std::int64_t> target;
  const StackingObject* best = nullptr;
  for (const auto& [id, o] : objects_) {
    if (o.role != ObjectRole::kStacked) continue;
    if (!best || o.role_since_s > best->role_since_s ||
        (o.role_since_s == best->role_since_s && o.ellipse.cy < best->ellipse.cy)) {
      best = &o;
    }
  }
  if (best) target = best->track_id;
  if (target != target_) {
    target_ = target;
    if (target) events.push_back({StackingEvent::kTargetChanged, *target, stamp_s});
  }
  return events;
}

std::vector<StackingObject> StackingMonitor::NewObjects() const {
  std::vector<StackingObject> out;
  for (const auto& [id, o] : objects_)
    if (o.role == ObjectRole::kNew) out.push_back(o);
  return out;
}

std::vector<StackingObject> StackingMonitor::StackedObjects() const {
  std::vector<StackingObject> out;
  for (const auto& [id, o] : objects_)
    if (o.role == ObjectRole::kStacked) out.push_back(o);
  return out;
}

std::optional<StackingObject> StackingMonitor::NextStackingTarget() const {
  if (!target_) return std::nullopt;
  auto it = objects_.find(*target_);
  if (it == objects_.end()) return std::nullopt;
  return it->second;
}

}  // namespace ellipsekit::robot
