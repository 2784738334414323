#include "base_station/core/robot_frame_objects.h"

#include <cmath>
#include <cstdio>
#include <limits>

namespace cairn::base {

std::vector<GlobalObject> robot_frame_objects(const MapperData& data, const ObjectMergeOptions& merge) {
  std::map<RobotId, std::vector<PlacedObjectReport>> by_robot;
  for (const auto& [id, r] : data.reports) {
    const KeyframeId anchor{id.robot, r.anchor_seq};
    if (data.linked(id.robot) || !data.keyframes.count(anchor)) continue;
    by_robot[id.robot].push_back(
        PlacedObjectReport{&r, data.refined_local_pose(anchor).to_isometry3() * r.T_anchor_object});
  }
  std::vector<GlobalObject> out;
  for (const auto& [robot, placed] : by_robot) {
    for (GlobalObject& o : merge_object_reports(placed, merge)) {
      o.frame = robot;
      out.push_back(std::move(o));
    }
  }
  return out;
}

void update_robot_frame_map(const MapperData& data, RobotId robot, const std::vector<GlobalObject>& unplaced,
                            GlobalMapRenderer* renderer, RobotFrameMap* map) {
  map->robot = robot;
  map->trajectory.clear();
  for (const auto& [id, kf] : data.robot_keyframes(robot)) {
    const SE2 pose = data.refined_local_pose(id);
    renderer->set_pose(kf, pose);
    map->trajectory.push_back(StampedPose{kf.stamp_ns, pose});
  }
  map->grid = renderer->render();
  map->objects.clear();
  for (const GlobalObject& o : unplaced) {
    if (o.frame == robot) map->objects.push_back(o);
  }
}

std::string frame_name(RobotId frame) { return frame.valid() ? "robot" + std::to_string(frame.value) : "global"; }

FromEntry from_entry(const MapperData& data, RobotId robot, const Eigen::Vector2d& p_local_m) {
  FromEntry w;
  w.distance_m = p_local_m.norm();
  w.bearing_rad = std::atan2(p_local_m.y(), p_local_m.x());
  double along_m = 0, best_m = std::numeric_limits<double>::infinity();
  const Keyframe* prev = nullptr;
  for (const auto& [id, kf] : data.robot_keyframes(robot)) {
    const SE2 pose = data.refined_local_pose(id);
    if (prev) along_m += data.refined_local_pose(prev->id).between(pose).translation().norm();
    const double d = (pose.translation() - p_local_m).norm();
    if (d < best_m) {
      best_m = d;
      w.path_m = along_m;
    }
    prev = &kf;
  }
  return w;
}

std::string describe(RobotId robot, const FromEntry& where) {
  const double deg = where.bearing_rad * 180.0 / M_PI;
  char text[160];
  std::snprintf(text, sizeof(text),
                "%.1f m from where robot %d entered, %.0f deg %s of its heading there (%.0f m along its path)",
                where.distance_m, robot.value, std::abs(deg), deg >= 0 ? "left" : "right", where.path_m);
  return text;
}

}  // namespace cairn::base
