#pragma once
// Comparing a base's results with a multi-robot log's reference (TRUTH and MARKER records).
//   const GlobalFrame f = global_frame_of(log, summary_json);   // how the base's global frame sits in the world
//   Eigen::Vector2d p_global = f.T_global_world * p_world;
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "common/multirobot_log.h"

namespace cairn::mrlog {

struct GlobalFrame {
  SE2 T_global_world;
  std::string description;  ///< e.g. "robot 0's start" or "the start given for robot 2"
};

/// The base's global frame in the log's world frame. When the base was given a robot's start
/// (`cairn_base --start`, written to summary.json as robots[].given_start), the global frame is the
/// frame that start was given in; otherwise it is the anchor robot's start frame (robots[].anchor,
/// else the lowest id). nullopt when the robot it needs has no TRUTH records.
std::optional<GlobalFrame> global_frame_of(const MultiRobotLog& log, const nlohmann::json& summary);

}  // namespace cairn::mrlog
