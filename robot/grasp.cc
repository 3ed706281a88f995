// Pre-grasp and grasp poses for an object on the conveyor (see grasp.h).
#include "ellipsekit/robot/grasp.h"

#include <cmath>

#include <Eigen/Geometry>

namespace ellipsekit::robot {

Result<Quaternion> GripperOrientation(const Eigen::Vector3d& approach, const Eigen::Vector3d& up) {
  using R = Result<Quaternion>;
  if (!approach.allFinite() || !up.allFinite() || approach.norm() == 0 || up.norm() == 0) {
    return R::Error(StatusCode::kInvalidArgument, "grasp: zero approach or up vector");
  }
  const Eigen::Vector3d z = approach.normalized();
  Eigen::Vector3d y = up.normalized().cross(z);
  if (y.norm() < 1e-6) return R::Error(StatusCode::kInvalidArgument, "grasp: approach parallel to up");
  y.normalize();
  Eigen::Matrix3d Rm;
  Rm.col(0) = y.cross(z);
  Rm.col(1) = y;
  Rm.col(2) = z;
  const Eigen::Quaterniond q(Rm);
  return R::Ok(Quaternion{q.x(), q.y(), q.z(), q.w()});
}

Result<GraspPlan> PlanConveyorGrasp(const ConveyorTracker& conveyor, double now_s, const GraspOptions& o) {
  using R = Result<GraspPlan>;
  auto orient = GripperOrientation(o.approach, o.up);
  if (!orient.ok()) return R{orient.status, {}};
  auto st = conveyor.State();
  if (!st.ok()) return R{st.status, {}};
  const double v = st.value.speed_m_s;
  const double t_arrive = now_s + o.latency_s;  // the gripper is at the pre-grasp pose
  const double s_then = st.value.position_m + v * (t_arrive - st.value.stamp_s);
  GraspPlan plan;
  plan.speed_m_s = v;
  if (std::abs(v) >= o.min_speed_m_s) {
    plan.grasp_position_m = s_then + (v > 0 ? o.lead_m : -o.lead_m);
    plan.grasp_time_s = t_arrive + o.lead_m / std::abs(v);
  } else {
    plan.grasp_position_m = s_then;
    plan.grasp_time_s = t_arrive;
  }
  const bool inside = plan.grasp_position_m >= o.range_margin_m &&
                      plan.grasp_position_m <= conveyor.length_m() - o.range_margin_m;
  plan.decision = inside ? GraspDecision::kGrasp : GraspDecision::kWaitForReturn;

  const Eigen::Vector3d g = conveyor.PositionToPoint(plan.grasp_position_m);
  const Eigen::Vector3d pre = g - o.pregrasp_offset_m * o.approach.normalized();
  Header h;
  h.frame_id = conveyor.frame_id();
  h.stamp = Time::FromSeconds(plan.grasp_time_s);
  plan.grasp.header = h;
  plan.grasp.pose.position = Point{g.x(), g.y(), g.z()};
  plan.grasp.pose.orientation = orient.value;
  plan.pregrasp.header = h;
  plan.pregrasp.header.stamp = Time::FromSeconds(t_arrive);
  plan.pregrasp.pose.position = Point{pre.x(), pre.y(), pre.z()};
  plan.pregrasp.pose.orientation = orient.value;
  return R::Ok(plan);
}

}  // namespace ellipsekit::robot
