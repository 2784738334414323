#pragma once
// MergedMap: what the outputs read of the merger (exports, the exploration planner, the console
// snapshot): the global grid, the robots, their trajectories and the merged objects, and for the
// exports that need them the stored data and the pose graph. MultiRobotMapper::merged() makes it;
// it points into the mapper, so it is valid until the mapper next changes.
#include <cstdint>
#include <map>
#include <vector>

#include "base_station/core/global_object.h"
#include "base_station/core/keyframe_pose_graph.h"
#include "base_station/core/mapper_data.h"
#include "base_station/core/mapper_results.h"
#include "base_station/core/robot_frame_objects.h"
#include "common/occupancy_grid.h"
#include "common/trajectory.h"

namespace cairn::base {

struct MergedMap {
  const OccupancyGrid* grid = nullptr;         ///< every linked keyframe's scan at its global pose
  const MapperData* data = nullptr;            ///< what the mapper stored (keyframes, object reports)
  const KeyframePoseGraph* graph = nullptr;    ///< the pose graph as last optimised
  std::vector<RobotSummary> robots;            ///< every robot heard of, by id
  std::map<RobotId, Trajectory> trajectories;  ///< linked robots' keyframe poses in the global frame
  std::vector<GlobalObject> objects;           ///< merged objects of linked robots, by id
  /// Objects of robots not linked yet, in their robot's own frame (GlobalObject::frame), by id.
  std::vector<GlobalObject> unplaced_objects;
  const std::vector<RobotFrameMap>* robot_frame_maps = nullptr;  ///< each unlinked robot's own map, by robot
  std::map<RobotId, AlignmentVerdict> alignments;  ///< the operator's latest alignment of each robot, judged
  uint64_t version = 0;                            ///< MultiRobotMapper::version() when made

  /// Every object the team is shown: the placed ones, then the unplaced ones.
  std::vector<const GlobalObject*> all_objects() const {
    std::vector<const GlobalObject*> all;
    for (const GlobalObject& o : objects) all.push_back(&o);
    for (const GlobalObject& o : unplaced_objects) all.push_back(&o);
    return all;
  }

  /// Every robot heard of, with T_global_local once it is linked (nullopt before): what goal and
  /// command frames are turned with.
  std::map<RobotId, std::optional<SE2>> placements() const {
    std::map<RobotId, std::optional<SE2>> out;
    for (const RobotSummary& r : robots) out[r.id] = r.linked ? std::optional<SE2>(r.T_global_local) : std::nullopt;
    return out;
  }

  /// A linked robot's trajectory (empty when it is not linked).
  const Trajectory& trajectory(RobotId robot) const {
    static const Trajectory kNone;
    const auto it = trajectories.find(robot);
    return it == trajectories.end() ? kNone : it->second;
  }
};

}  // namespace cairn::base
