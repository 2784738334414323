#include "robot_agent/core/navigation/operator_orders.h"

#include <gtest/gtest.h>

namespace cairn::agent {
namespace {

OperatorCommand command(uint32_t seq, CommandKind kind, Eigen::Vector2d goal_m = {0, 0}) {
  return {RobotId(1), seq, kind, goal_m};
}

TEST(OperatorOrders, GotoDrivesThenHoldsAtThePointUntilResumed) {
  OperatorOrders o;
  EXPECT_FALSE(o.in_control());
  ASSERT_TRUE(o.take(command(1, CommandKind::kGoTo, {4, -2})));
  EXPECT_EQ(o.next_action(), OperatorAction::kDriveTo);
  EXPECT_EQ(o.next_action(), OperatorAction::kNone);  // once
  EXPECT_EQ(o.goal_m(), Eigen::Vector2d(4, -2));
  EXPECT_EQ(o.activity(), RobotActivity::kOperatorGoal);
  EXPECT_EQ(o.report().state, CommandState::kActive);
  o.on_navigation(NavState::kDriving, "");
  EXPECT_FALSE(o.holding());
  o.on_navigation(NavState::kReached, "");
  EXPECT_TRUE(o.holding());
  EXPECT_EQ(o.activity(), RobotActivity::kHeld);
  EXPECT_EQ(o.report().seq, 1u);
  EXPECT_EQ(o.report().state, CommandState::kDone);
  ASSERT_TRUE(o.take(command(2, CommandKind::kResume)));
  EXPECT_EQ(o.next_action(), OperatorAction::kRelease);
  EXPECT_FALSE(o.in_control());
  EXPECT_EQ(o.report().state, CommandState::kDone);
}

TEST(OperatorOrders, AnUnreachablePointFailsWithTheNavigatorsReasonAndHolds) {
  OperatorOrders o;
  o.take(command(3, CommandKind::kGoTo, {40, 0}));
  o.next_action();
  o.on_navigation(NavState::kUnreachable, "no path on its map");
  EXPECT_TRUE(o.holding());
  EXPECT_EQ(o.report().state, CommandState::kFailed);
  EXPECT_NE(o.report().note.find("no path on its map"), std::string::npos) << o.report().note;
}

TEST(OperatorOrders, TheOldStateOfAReplacedGoalDoesNotEndTheNewOne) {
  OperatorOrders o;
  o.take(command(1, CommandKind::kGoTo, {1, 0}));
  o.next_action();
  o.take(command(2, CommandKind::kGoTo, {9, 0}));
  // The navigator still says "reached" for the first point until the node sets the new goal.
  o.on_navigation(NavState::kReached, "");
  EXPECT_EQ(o.report().state, CommandState::kActive);
  EXPECT_EQ(o.next_action(), OperatorAction::kDriveTo);
  EXPECT_EQ(o.goal_m(), Eigen::Vector2d(9, 0));
}

TEST(OperatorOrders, StopHoldsAtOnceAndOldOrRepeatedCommandsAreIgnored) {
  OperatorOrders o;
  ASSERT_TRUE(o.take(command(5, CommandKind::kStop)));
  EXPECT_EQ(o.next_action(), OperatorAction::kHold);
  EXPECT_TRUE(o.holding());
  EXPECT_EQ(o.report().state, CommandState::kDone);
  EXPECT_FALSE(o.take(command(5, CommandKind::kStop)));    // a resend after a reconnect
  EXPECT_FALSE(o.take(command(4, CommandKind::kResume)));  // older than the newest taken
  EXPECT_EQ(o.next_action(), OperatorAction::kNone);
  EXPECT_TRUE(o.holding());
  EXPECT_EQ(o.report().seq, 5u);
}

TEST(OperatorOrders, HomeIsHandedToTheMissionAndDoneOnlyOnceHome) {
  OperatorOrders o;
  o.take(command(1, CommandKind::kStop));
  o.next_action();
  ASSERT_TRUE(o.take(command(2, CommandKind::kHome)));
  EXPECT_EQ(o.next_action(), OperatorAction::kGoHome);
  EXPECT_FALSE(o.in_control());  // MissionBehaviour drives it home
  o.on_home(false);
  EXPECT_EQ(o.report().state, CommandState::kActive);
  o.on_home(true);
  EXPECT_EQ(o.report().state, CommandState::kDone);
  EXPECT_EQ(o.report().note, "home");
}

}  // namespace
}  // namespace cairn::agent
