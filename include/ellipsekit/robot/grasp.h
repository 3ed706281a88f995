// Grasp poses for an object on the conveyor (paper sec. V-B).
//
// At time `now`, the robot needs `latency_s` to reach the pre-grasp pose. The object's position
// is predicted at now + latency (the "newest position" when the robot is there); the grasp
// target is `lead_m` (2 cm) ahead of it in the direction of motion, and the object reaches the
// target at grasp_time = now + latency + lead / |speed|. The pre-grasp pose is `pregrasp_offset_m`
// (10 cm) back from the grasp along the approach vector. When the target leaves the guide's range
// [margin, length - margin], the plan says to wait for the return phase.
//
// Gripper orientation: z axis = approach vector (the normal to the palm), y axis = the closing
// direction, horizontal (up x approach), x = y x z. All in the conveyor's output frame.
#pragma once

#include <Eigen/Core>

#include "ellipsekit/robot/conveyor.h"
#include "ellipsekit/robot/messages.h"

namespace ellipsekit::robot {

struct GraspOptions {
  double latency_s = 1.0;          // time from planning to the gripper at the pre-grasp pose
  double lead_m = 0.02;            // grasp this far ahead of the object's position
  double pregrasp_offset_m = 0.10; // pre-grasp this far back along the approach vector
  double range_margin_m = 0.0;     // keep the grasp this far inside the guide's ends
  double min_speed_m_s = 0.005;    // slower objects are treated as static (no lead)
  Eigen::Vector3d approach{0, 1, 0};  // output frame; need not be unit; not parallel to up
  Eigen::Vector3d up{0, 0, 1};        // output frame (REP 103: base_link z up)
};

enum class GraspDecision {
  kGrasp,          // poses are valid
  kWaitForReturn,  // the target falls outside the guide; wait for the return phase
};

struct GraspPlan {
  GraspDecision decision = GraspDecision::kWaitForReturn;
  PoseStamped pregrasp;
  PoseStamped grasp;
  double grasp_time_s = 0;       // when the object is at the grasp pose
  double grasp_position_m = 0;   // along the guide
  double speed_m_s = 0;
};

// Fails when the conveyor has no speed estimate yet or the approach vector is degenerate.
Result<GraspPlan> PlanConveyorGrasp(const ConveyorTracker& conveyor, double now_s,
                                    const GraspOptions& options = {});

// Orientation with z = approach and y = normalize(up x approach). Fails when they are parallel.
Result<Quaternion> GripperOrientation(const Eigen::Vector3d& approach, const Eigen::Vector3d& up);

}  // namespace ellipsekit::robot
