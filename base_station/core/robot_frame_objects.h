#pragma once
// Objects of robots the base has not linked yet, in each robot's own local frame, so that no find
// stays hidden from the team while the robots wait to be placed on the global map ("no victim
// hidden"). A robot's local frame starts where it entered: x ahead along its heading at entry, y to
// its left. The reports are merged per robot exactly as the global ones are (merge_object_reports),
// placed through their anchor keyframes' refined local poses.
#include <string>
#include <vector>

#include "base_station/core/global_map_renderer.h"
#include "base_station/core/global_object.h"
#include "base_station/core/mapper_data.h"
#include "common/occupancy_grid.h"
#include "common/trajectory.h"

namespace cairn::base {

/// Every unlinked robot's objects (reports whose anchor keyframe is stored), GlobalObject::frame set
/// to the robot; by robot, then id.
std::vector<GlobalObject> robot_frame_objects(const MapperData& data, const ObjectMergeOptions& merge);

/// A robot's own map, for the team while the base cannot place it yet.
struct RobotFrameMap {
  RobotId robot;
  OccupancyGrid grid;                 ///< its keyframes' scans at their refined local poses
  Trajectory trajectory;              ///< its keyframes in its own frame
  std::vector<GlobalObject> objects;  ///< its objects (GlobalObject::frame == robot)
};
/// Brings robot's own map up to date: its keyframes at their refined local poses handed to
/// `renderer` (kept per robot by the caller: it redraws only what is new or moved, as the global
/// map's does), its objects taken from `unplaced`.
void update_robot_frame_map(const MapperData& data, RobotId robot, const std::vector<GlobalObject>& unplaced,
                            GlobalMapRenderer* renderer, RobotFrameMap* map);

/// "global", or "robotN" for an object in robot N's own frame (GlobalObject::frame).
std::string frame_name(RobotId frame);

/// Where a point of a robot's local frame is, told from where the robot entered.
struct FromEntry {
  double distance_m = 0;   ///< straight line from the entry point
  double bearing_rad = 0;  ///< from the heading at entry, counter-clockwise (left) positive
  double path_m = 0;       ///< along the robot's path to its keyframe nearest the point
};
FromEntry from_entry(const MapperData& data, RobotId robot, const Eigen::Vector2d& p_local_m);
/// "12.3 m from where robot 1 entered, 40 deg left of its heading there (18 m along its path)".
std::string describe(RobotId robot, const FromEntry& where);

}  // namespace cairn::base
