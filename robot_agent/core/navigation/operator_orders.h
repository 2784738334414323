#pragma once
// The operator's commands on board (the decisions; the node drives). An operator's command
// outranks the base's goals and the robot's own exploration until the operator resumes it:
//   - goto: drive to the point, then hold there (the operator sent it to look at something);
//     no path or stuck: hold where it is and report the command failed, with the navigator's reason;
//   - stop: hold still at once;
//   - resume: back to autonomy (the base's newest goal, or its own exploration);
//   - home: handed to MissionBehaviour as a "go home" goal, so the drive home, its retries and the
//     end of the mission are the same as when the base sends the team home; done once home.
// Commands carry a sequence number that grows over the mission: an older or repeated one (a DDS
// resend after a reconnect) is ignored. The robot reports the newest command's state in its status.
// Pure: commands and navigation states in, actions and a report out.
#include <Eigen/Core>
#include <optional>
#include <string>

#include "common/navigation.h"

namespace cairn::agent {

/// What the node must do now about the operator.
enum class OperatorAction {
  kNone,     ///< nothing new
  kDriveTo,  ///< set the navigator's goal to goal_m()
  kHold,     ///< cancel the navigator's goal; command zero velocity from now on
  kRelease,  ///< autonomy again: drive MissionBehaviour's target
  kGoHome,   ///< tell MissionBehaviour to go home, then release
};

class OperatorOrders {
 public:
  /// A command from the base. False (and nothing changes) for one older than or equal to the
  /// newest taken.
  bool take(const OperatorCommand& command);

  /// The action the newest command asks for, once (kNone afterwards).
  OperatorAction next_action();

  /// While a goto is driven: the navigator's state for it and its reason. Reached: done, hold.
  /// Unreachable or stuck: failed (the note says why), hold.
  void on_navigation(NavState state, const std::string& reason);
  /// While a home command is carried out: whether MissionBehaviour says the robot is home.
  void on_home(bool home);

  /// The operator holds the robot still (after stop, or at or short of a goto's point).
  bool holding() const { return mode_ == Mode::kHolding; }
  /// The operator decides where the robot drives (a goto being driven, or holding).
  bool in_control() const { return mode_ != Mode::kAutonomous; }
  /// kOperatorGoal or kHeld while in control.
  RobotActivity activity() const;
  const Eigen::Vector2d& goal_m() const { return command_.goal_m; }
  const CommandReport& report() const { return report_; }

 private:
  enum class Mode { kAutonomous, kDriving, kHolding };
  OperatorCommand command_;
  CommandReport report_;
  Mode mode_ = Mode::kAutonomous;
  OperatorAction pending_ = OperatorAction::kNone;
  bool going_home_ = false;  ///< a home command, handed to MissionBehaviour, not home yet
};

}  // namespace cairn::agent
