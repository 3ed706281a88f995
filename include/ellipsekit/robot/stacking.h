// Region states of the stacking task (paper sec. V-A): a person feeds cans on one side of the
// table ("feed side", e.g. the right); the robot stacks them on the other side. A track seen on the
// feed side is a new object; once it crosses to the stack side it becomes stacked (same id); the
// next stacking target is the stacked object that arrived most recently (the top of the newest
// stack: lower cans are hidden by the one placed on them).
//
// The regions are split by an image line through two pixels; `feed_side_pixel` is any pixel on
// the feed side.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "ellipsekit/robot/tracker.h"

namespace ellipsekit::robot {

enum class ObjectRole { kNew, kStacked };

struct StackingRegions {
  Eigen::Vector2d line_p0{320, 0};
  Eigen::Vector2d line_p1{320, 480};
  Eigen::Vector2d feed_side_pixel{640, 240};
};

struct StackingObject {
  std::int64_t track_id = 0;
  ObjectRole role = ObjectRole::kNew;
  Ellipse ellipse;
  double role_since_s = 0;  // when the object entered its current role
};

struct StackingEvent {
  enum Kind { kNewObject, kObjectStacked, kTargetChanged } kind;
  std::int64_t track_id;
  double stamp_s;
};

class StackingMonitor {
 public:
  explicit StackingMonitor(StackingRegions regions) : regions_(regions) {}

  // Reads the confirmed tracks of one frame; returns what changed.
  std::vector<StackingEvent> Update(const std::vector<Track>& tracks, double stamp_s);

  bool OnFeedSide(const Eigen::Vector2d& pixel) const;
  std::vector<StackingObject> NewObjects() const;
  std::vector<StackingObject> StackedObjects() const;
  // The object to stack the next can on; none before the first stack.
  std::optional<StackingObject> NextStackingTarget() const;

 private:
  StackingRegions regions_;
  std::map<std::int64_t, StackingObject> objects_;
  std::optional<std::int64_t> target_;
};

}  // namespace ellipsekit::robot
