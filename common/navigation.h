#pragma once
// The navigation vocabulary the base and the agents share (goals on cairn/goal, the operator's
// commands on cairn/operator_command, state on cairn/status, velocities on cairn/robot<N>/cmd_vel).
// The numeric values are the wire values.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>

#include "common/ids.h"
#include "common/se2.h"
#include "common/time.h"

namespace cairn {

/// What the base asks of a robot.
enum class GoalKind : uint8_t {
  kOwn = 0,      ///< no goal from the base: explore the robot's own map (it is not placed yet)
  kExplore = 1,  ///< drive to this frontier of the merged map
  kHome = 2,     ///< nothing left to explore: drive back to where you entered
  /// Drive toward a teammate so that the base can link the two (base_station/core/active_linking.h):
  /// sent to a robot not placed yet, and to the placed teammate it is to meet.
  kMeet = 3,
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
  kHome = 5,          ///< back where it entered: its mission is over
  kOperatorGoal = 6,  ///< driving to the point the operator clicked
  kHeld = 7,          ///< held still by the operator (stopped, or at the operator's point)
  kMeeting = 8,       ///< driving the base's kMeet goal: toward a teammate, to be linked
};

/// An operator's command from the console (cairn/operator_command). Every kind can be sent to one
/// robot or, by the base, to each robot in turn.
enum class CommandKind : uint8_t {
  kGoTo = 0,    ///< drive to a point and hold there until resumed
  kStop = 1,    ///< stop where it is and hold until resumed
  kResume = 2,  ///< back to autonomous exploration
  kHome = 3,    ///< drive back to where it entered; its mission is then over
};

/// What became of a command. The agent reports kReceived..kFailed for the newest command it got;
/// the base adds kSent (not acknowledged yet) and kOvertaken (a newer command to the same robot
/// arrived first, so this one was never carried out).
enum class CommandState : uint8_t {
  kSent = 0,
  kReceived = 1,  ///< acknowledged by the robot
  kActive = 2,    ///< being carried out (driving there, or driving home)
  kDone = 3,
  kRefused = 4,  ///< the robot would not take it (the note says why)
  kFailed = 5,   ///< taken, but it could not be carried out (no path, stuck)
  kOvertaken = 6,
};

inline const char* to_string(GoalKind k) {
  switch (k) {
    case GoalKind::kOwn:
      return "own";
    case GoalKind::kExplore:
      return "explore";
    case GoalKind::kHome:
      return "home";
    case GoalKind::kMeet:
      return "meet";
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
    case RobotActivity::kOperatorGoal:
      return "driving to the operator's point";
    case RobotActivity::kHeld:
      return "held by the operator";
    case RobotActivity::kMeeting:
      return "meeting a teammate";
  }
  return "?";
}
inline const char* to_string(CommandKind k) {
  switch (k) {
    case CommandKind::kGoTo:
      return "goto";
    case CommandKind::kStop:
      return "stop";
    case CommandKind::kResume:
      return "resume";
    case CommandKind::kHome:
      return "home";
  }
  return "?";
}
inline const char* to_string(CommandState s) {
  switch (s) {
    case CommandState::kSent:
      return "sent";
    case CommandState::kReceived:
      return "acknowledged";
    case CommandState::kActive:
      return "active";
    case CommandState::kDone:
      return "done";
    case CommandState::kRefused:
      return "refused";
    case CommandState::kFailed:
      return "failed";
    case CommandState::kOvertaken:
      return "overtaken";
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

/// cairn/operator_command: the operator's newest command to one robot, in the robot's own frame.
/// Sequence numbers grow over the whole mission (all robots), so a newer command has a larger one.
struct OperatorCommand {
  RobotId robot;
  uint32_t seq = 0;
  CommandKind kind = CommandKind::kStop;
  Eigen::Vector2d goal_m{0, 0};  ///< kGoTo only
};

/// The robot's word on the newest command it received (part of cairn/status).
struct CommandReport {
  uint32_t seq = 0;  ///< 0: no command received yet
  CommandState state = CommandState::kReceived;
  std::string note;  ///< why refused or failed, or what it is doing
};

/// The navigation part of cairn/status.
struct NavStatus {
  SE2 pose;  ///< in the robot's own frame
  RobotActivity activity = RobotActivity::kWaiting;
  uint32_t goal_id = 0;
  GoalKind goal_kind = GoalKind::kOwn;
  NavState nav_state = NavState::kIdle;
  Eigen::Vector2d goal_m{0, 0};   ///< in the robot's own frame
  double distance_m = 0;          ///< driven so far
  CommandReport command;          ///< the operator's newest command, as the robot sees it
  uint32_t keep_out_version = 0;  ///< the operator's keep-out areas it holds (KeepOutMessage::version)
  /// The path it is driving, ahead of it, in its own frame (at most kMaxStatusPathPoints).
  std::vector<Eigen::Vector2d> path_m;
};
/// Points of the planned path a status carries (RobotStatus.path_x_m: a bounded sequence).
constexpr size_t kMaxStatusPathPoints = 32;

/// Wire value -> enum; nullopt for a value no version of Cairn sends.
inline std::optional<GoalKind> goal_kind_from(uint8_t v) {
  return v <= 3 ? std::optional<GoalKind>(GoalKind(v)) : std::nullopt;
}
inline std::optional<NavState> nav_state_from(uint8_t v) {
  return v <= 4 ? std::optional<NavState>(NavState(v)) : std::nullopt;
}
inline std::optional<RobotActivity> robot_activity_from(uint8_t v) {
  return v <= 8 ? std::optional<RobotActivity>(RobotActivity(v)) : std::nullopt;
}
inline std::optional<CommandKind> command_kind_from(uint8_t v) {
  return v <= 3 ? std::optional<CommandKind>(CommandKind(v)) : std::nullopt;
}
inline std::optional<CommandState> command_state_from(uint8_t v) {
  return v <= 6 ? std::optional<CommandState>(CommandState(v)) : std::nullopt;
}

}  // namespace cairn
