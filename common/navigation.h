#pragma once
// The navigation vocabulary the base and the agents share (goals on cairn/goal, state on
// cairn/status, commands on cairn/robot<N>/cmd_vel). The numeric values are the wire values.
#include <Eigen/Core>
#include <cstdint>
#include <optional>

#include "common/ids.h"
#include "common/se2.h"
#include "common/time.h"

namespace cairn {

/// What the base asks of a robot.
enum class GoalKind : uint8_t {
  kOwn = 0,      ///< no goal from the base: explore the robot's own map (it is not placed yet)
  kExplore = 1,  ///< drive to this frontier of the merged map
  kHome = 2,     ///< nothing left to explore: drive back to where you entered
};

/// The state of the goal a robot is driving (robot_agent/core/navigation/goal_tracker.h).
enum class NavState : uint8_t {
  kIdle = 0,
  kDriving = 1,
  kReached = 2,
  kUnreachable = 3,  ///< no path on the robot's map
  kStuck = 4,        ///< no progress for a while
};

/// What a robot is doing, as its agent decides (robot_agent/core/navigation/mission_behaviour.h).
enum class RobotActivity : uint8_t {
  kWaiting = 0,             ///< no goal yet
  kExploring = 1,           ///< driving the base's goal
  kOwnExploration = 2,      ///< the nearest frontier of its own map (not placed, or out of contact)
  kReturningToContact = 3,  ///< out of contact too long: back to where it last heard the base
  kGoingHome = 4,
  kHome = 5,  ///< back where it entered: its mission is over
};

inline const char* to_string(GoalKind k) {
  switch (k) {
    case GoalKind::kOwn:
      return "own";
    case GoalKind::kExplore:
      return "explore";
    case GoalKind::kHome:
      return "home";
  }
  return "?";
}
inline const char* to_string(NavState s) {
  switch (s) {
    case NavState::kIdle:
      return "idle";
    case NavState::kDriving:
      return "driving";
    case NavState::kReached:
      return "reached";
    case NavState::kUnreachable:
      return "unreachable";
    case NavState::kStuck:
      return "stuck";
  }
  return "?";
}
inline const char* to_string(RobotActivity a) {
  switch (a) {
    case RobotActivity::kWaiting:
      return "waiting";
    case RobotActivity::kExploring:
      return "exploring";
    case RobotActivity::kOwnExploration:
      return "exploring on its own";
    case RobotActivity::kReturningToContact:
      return "returning to contact";
    case RobotActivity::kGoingHome:
      return "going home";
    case RobotActivity::kHome:
      return "home";
  }
  return "?";
}

/// A velocity command to a differential-drive base (the shape of a ROS cmd_vel).
struct VelocityCommand {
  double linear_mps = 0.0;
  double angular_radps = 0.0;
};

/// cairn/robot<N>/cmd_vel: the agent's command answering its scan at stamp_ns.
struct StampedCommand {
  RobotId robot;
  StampNs stamp_ns = 0;
  VelocityCommand command;
  bool done = false;  ///< the robot is home (or gave up): its mission is over
};

/// cairn/goal: the base's order to one robot, in the robot's own frame.
struct GoalMessage {
  RobotId robot;
  uint32_t goal_id = 0;
  GoalKind kind = GoalKind::kOwn;
  bool has_goal = false;
  Eigen::Vector2d goal_m{0, 0};
  double path_m = 0;
  double frontier_m = 0;
};

/// The navigation part of cairn/status.
struct NavStatus {
  SE2 pose;  ///< in the robot's own frame
  RobotActivity activity = RobotActivity::kWaiting;
  uint32_t goal_id = 0;
  GoalKind goal_kind = GoalKind::kOwn;
  NavState nav_state = NavState::kIdle;
  Eigen::Vector2d goal_m{0, 0};  ///< in the robot's own frame
  double distance_m = 0;         ///< driven so far
};

/// Wire value -> enum; nullopt for a value no version of Cairn sends.
inline std::optional<GoalKind> goal_kind_from(uint8_t v) {
  return v <= 2 ? std::optional<GoalKind>(GoalKind(v)) : std::nullopt;
}
inline std::optional<NavState> nav_state_from(uint8_t v) {
  return v <= 4 ? std::optional<NavState>(NavState(v)) : std::nullopt;
}
inline std::optional<RobotActivity> robot_activity_from(uint8_t v) {
  return v <= 5 ? std::optional<RobotActivity>(RobotActivity(v)) : std::nullopt;
}

}  // namespace cairn
