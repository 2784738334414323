#include "robot_agent/core/navigation/operator_orders.h"

namespace cairn::agent {

bool OperatorOrders::take(const OperatorCommand& command) {
  if (command.seq <= report_.seq) return false;
  command_ = command;
  report_ = {command.seq, CommandState::kReceived, ""};
  going_home_ = false;
  switch (command.kind) {
    case CommandKind::kGoTo:
      mode_ = Mode::kDriving;
      pending_ = OperatorAction::kDriveTo;
      report_.state = CommandState::kActive;
      report_.note = "driving to the operator's point";
      break;
    case CommandKind::kStop:
      mode_ = Mode::kHolding;
      pending_ = OperatorAction::kHold;
      report_.state = CommandState::kDone;
      report_.note = "stopped; holding until resumed";
      break;
    case CommandKind::kResume:
      mode_ = Mode::kAutonomous;
      pending_ = OperatorAction::kRelease;
      report_.state = CommandState::kDone;
      report_.note = "exploring on its own again";
      break;
    case CommandKind::kHome:
      mode_ = Mode::kAutonomous;
      pending_ = OperatorAction::kGoHome;
      going_home_ = true;
      report_.state = CommandState::kActive;
      report_.note = "driving home";
      break;
  }
  return true;
}

OperatorAction OperatorOrders::next_action() {
  const OperatorAction a = pending_;
  pending_ = OperatorAction::kNone;
  return a;
}

void OperatorOrders::on_navigation(NavState state, const std::string& reason) {
  if (mode_ != Mode::kDriving || pending_ != OperatorAction::kNone) return;
  if (state == NavState::kReached) {
    mode_ = Mode::kHolding;
    report_.state = CommandState::kDone;
    report_.note = "reached the point; holding until resumed";
  } else if (state == NavState::kUnreachable || state == NavState::kStuck) {
    mode_ = Mode::kHolding;
    report_.state = CommandState::kFailed;
    report_.note = std::string(to_string(state)) + (reason.empty() ? "" : ": " + reason) + "; holding until resumed";
  }
}

void OperatorOrders::on_home(bool home) {
  if (!going_home_ || !home) return;
  going_home_ = false;
  report_.state = CommandState::kDone;
  report_.note = "home";
}

RobotActivity OperatorOrders::activity() const {
  return mode_ == Mode::kDriving ? RobotActivity::kOperatorGoal : RobotActivity::kHeld;
}

}  // namespace cairn::agent
