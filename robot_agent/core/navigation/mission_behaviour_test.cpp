#include "robot_agent/core/navigation/mission_behaviour.h"

#include <gtest/gtest.h>

namespace cairn::agent {
namespace {

StampNs at(double s) { return sec_to_ns(s); }

/// An own-frontier search over a fixed list: the first point not within 1 m of the blacklist.
OwnFrontierSearch frontiers(std::vector<Eigen::Vector2d> points) {
  return [points](const std::vector<Eigen::Vector2d>& blacklist) -> std::optional<Eigen::Vector2d> {
    for (const auto& p : points) {
      bool banned = false;
      for (const auto& b : blacklist) banned = banned || (p - b).norm() < 1.0;
      if (!banned) return p;
    }
    return std::nullopt;
  };
}

const Eigen::Vector2d kHere(1, 1);
const Eigen::Vector2d kFar(20, 20);  // where the robot is when it decides (far from home)

TEST(MissionBehaviour, DrivesTheBaseGoalThenWaitsForTheNextOne) {
  MissionBehaviour b;
  b.on_base_goal({7, GoalKind::kExplore, true, {5, 2}}, at(1), kHere);
  auto t = b.update(at(1), kFar, NavState::kIdle, frontiers({{9, 9}}));
  ASSERT_TRUE(t);
  EXPECT_EQ(t->goal_id, 7u);
  EXPECT_EQ(t->activity, RobotActivity::kExploring);
  EXPECT_EQ(t->position_m, Eigen::Vector2d(5, 2));
  EXPECT_FALSE(b.update(at(2), kFar, NavState::kDriving, frontiers({{9, 9}})));  // keeps driving
  b.on_contact(at(5), kHere);
  // Reached: it waits for the base's next goal...
  EXPECT_FALSE(b.update(at(5), kFar, NavState::kReached, frontiers({{9, 9}})));
  EXPECT_EQ(b.activity(), RobotActivity::kWaiting);
  b.on_contact(at(7), kHere);
  EXPECT_FALSE(b.update(at(7), kFar, NavState::kIdle, frontiers({{9, 9}})));
  // ...but not for ever: after base_wait_s it takes the nearest frontier of its own map.
  b.on_contact(at(9.5), kHere);
  t = b.update(at(9.5), kFar, NavState::kIdle, frontiers({{9, 9}}));
  ASSERT_TRUE(t);
  EXPECT_EQ(t->activity, RobotActivity::kOwnExploration);
  EXPECT_EQ(t->position_m, Eigen::Vector2d(9, 9));
  // A new base goal overrides its own exploration at once.
  b.on_base_goal({8, GoalKind::kExplore, true, {3, 3}}, at(10), kHere);
  t = b.update(at(10), kFar, NavState::kDriving, frontiers({{9, 9}}));
  ASSERT_TRUE(t);
  EXPECT_EQ(t->goal_id, 8u);
}

TEST(MissionBehaviour, AMeetingGoalIsDrivenAsMeetingThenItWaitsForTheBaseLikeAnyBaseGoal) {
  MissionBehaviour b;
  // Not placed yet: the base sends it toward a teammate (active linking), in its own frame.
  b.on_base_goal({4, GoalKind::kMeet, true, {6, -2}}, at(1), kHere);
  auto t = b.update(at(1), kFar, NavState::kIdle, frontiers({{9, 9}}));
  ASSERT_TRUE(t);
  EXPECT_EQ(t->goal_id, 4u);
  EXPECT_EQ(t->activity, RobotActivity::kMeeting);
  EXPECT_EQ(t->position_m, Eigen::Vector2d(6, -2));
  EXPECT_EQ(t->tolerance_m, MissionBehaviourOptions{}.meet_tolerance_m) << "a guess: any free cell near it";
  EXPECT_EQ(std::string(to_string(b.activity())), "meeting a teammate");
  // Reached (they met): it waits for the base, which links it and sends its next goal.
  b.on_contact(at(5), kHere);
  EXPECT_FALSE(b.update(at(5), kFar, NavState::kReached, frontiers({{9, 9}})));
  EXPECT_EQ(b.activity(), RobotActivity::kWaiting);
  b.on_contact(at(9.5), kHere);
  t = b.update(at(9.5), kFar, NavState::kIdle, frontiers({{9, 9}}));
  ASSERT_TRUE(t);
  EXPECT_EQ(t->activity, RobotActivity::kOwnExploration) << "no word after base_wait_s: its own frontiers";
}

TEST(MissionBehaviour, AnUnplacedRobotExploresItsOwnMapBlacklistingFailuresThenGoesHome) {
  MissionBehaviour b;
  b.on_base_goal({1, GoalKind::kOwn, false, {0, 0}}, at(0), kHere);
  auto t = b.update(at(0), kFar, NavState::kIdle, frontiers({{4, 0}, {8, 0}}));
  ASSERT_TRUE(t);
  EXPECT_EQ(t->activity, RobotActivity::kOwnExploration);
  EXPECT_EQ(t->position_m, Eigen::Vector2d(4, 0));
  b.on_contact(at(3), kHere);
  t = b.update(at(3), kFar, NavState::kUnreachable, frontiers({{4, 0}, {8, 0}}));
  ASSERT_TRUE(t);
  EXPECT_EQ(t->position_m, Eigen::Vector2d(8, 0)) << "the failed frontier is blacklisted on board";
  b.on_contact(at(6), kHere);
  t = b.update(at(6), kFar, NavState::kReached, frontiers({}));
  ASSERT_TRUE(t);
  EXPECT_EQ(t->activity, RobotActivity::kGoingHome);
  EXPECT_EQ(t->position_m, Eigen::Vector2d(0, 0));
  EXPECT_FALSE(b.done());
  b.on_contact(at(9), kHere);
  EXPECT_FALSE(b.update(at(9), kFar, NavState::kReached, frontiers({})));
  EXPECT_TRUE(b.done());
  EXPECT_EQ(b.activity(), RobotActivity::kHome);
}

TEST(MissionBehaviour, OutOfContactItExploresAloneThenReturnsToWhereItLastHeardTheBase) {
  MissionBehaviourOptions o;
  o.autonomy_after_s = 10;
  o.return_after_s = 30;
  MissionBehaviour b(o);
  b.on_base_goal({3, GoalKind::kExplore, true, {5, 0}}, at(0), {2, 2});
  ASSERT_TRUE(b.update(at(0), kFar, NavState::kIdle, frontiers({{9, 9}})));
  EXPECT_FALSE(b.update(at(8), kFar, NavState::kReached, frontiers({{9, 9}})));  // in contact: waits for the base
  auto t = b.update(at(12), kFar, NavState::kIdle, frontiers({{9, 9}}));
  ASSERT_TRUE(t) << "no word from the base for 12 s: it explores on its own";
  EXPECT_EQ(t->activity, RobotActivity::kOwnExploration);
  EXPECT_TRUE(b.out_of_contact(at(12)));
  t = b.update(at(31), kFar, NavState::kDriving, frontiers({{9, 9}}));
  ASSERT_TRUE(t) << "after return_after_s it turns back";
  EXPECT_EQ(t->activity, RobotActivity::kReturningToContact);
  EXPECT_EQ(t->position_m, Eigen::Vector2d(2, 2));
  EXPECT_FALSE(b.update(at(40), kFar, NavState::kReached, frontiers({{9, 9}})));  // waits there
  EXPECT_EQ(b.activity(), RobotActivity::kWaiting);
  b.on_base_goal({4, GoalKind::kExplore, true, {6, 6}}, at(45), {2, 2});
  t = b.update(at(45), kFar, NavState::kIdle, frontiers({{9, 9}}));
  ASSERT_TRUE(t);
  EXPECT_EQ(t->goal_id, 4u);
}

TEST(MissionBehaviour, HomeFromTheBaseIsRetriedThenGivenUp) {
  MissionBehaviourOptions o;
  o.max_home_attempts = 2;
  MissionBehaviour b(o);
  b.on_base_goal({5, GoalKind::kHome, true, {0, 0}}, at(0), kHere);
  auto t = b.update(at(0), kFar, NavState::kIdle, frontiers({}));
  ASSERT_TRUE(t);
  EXPECT_EQ(t->activity, RobotActivity::kGoingHome);
  EXPECT_DOUBLE_EQ(t->tolerance_m, 1.0);
  b.on_contact(at(5), kHere);
  EXPECT_FALSE(b.update(at(5), kFar, NavState::kStuck, frontiers({}))) << "one failure: it waits...";
  EXPECT_FALSE(b.update(at(7), kFar, NavState::kIdle, frontiers({})));
  t = b.update(at(10.5), kFar, NavState::kIdle, frontiers({}));
  ASSERT_TRUE(t) << "...then tries again";
  EXPECT_EQ(t->activity, RobotActivity::kGoingHome);
  EXPECT_FALSE(b.done());
  EXPECT_FALSE(b.update(at(12), kFar, NavState::kStuck, frontiers({})));
  EXPECT_TRUE(b.done());
  EXPECT_EQ(b.reason(), "gave up reaching home");
}

TEST(MissionBehaviour, StuckInTheHomeAreaIsHome) {
  MissionBehaviour b;
  b.on_base_goal({5, GoalKind::kHome, true, {0, 0}}, at(0), kHere);
  ASSERT_TRUE(b.update(at(0), kFar, NavState::kIdle, frontiers({})));
  b.on_contact(at(5), kHere);
  EXPECT_FALSE(b.update(at(5), {2.0, 1.5}, NavState::kStuck, frontiers({})));
  EXPECT_TRUE(b.done()) << "2.5 m from home, blocked: that is home";
  EXPECT_NE(b.reason().find("as near as it gets (250 cm off"), std::string::npos) << b.reason();
}

TEST(MissionBehaviour, TheSameGoalSentAgainChangesNothing) {
  MissionBehaviour b;
  b.on_base_goal({9, GoalKind::kExplore, true, {5, 2}}, at(0), kHere);
  ASSERT_TRUE(b.update(at(0), kFar, NavState::kIdle, frontiers({})));
  b.on_base_goal({9, GoalKind::kExplore, true, {5, 2}}, at(1), kHere);
  EXPECT_FALSE(b.update(at(1), kFar, NavState::kDriving, frontiers({})));
}

}  // namespace
}  // namespace cairn::agent

namespace cairn::agent {
namespace {

TEST(MissionBehaviour, ALaserLostTurnsItHomeAndTheBasesExplorationGoalsNoLongerCount) {
  MissionBehaviour b;
  b.on_base_goal({7, GoalKind::kExplore, true, {5, 2}}, at(1), kHere);
  ASSERT_TRUE(b.update(at(1), kFar, NavState::kIdle, frontiers({{9, 9}})));
  b.on_laser_lost();
  auto t = b.update(at(2), kFar, NavState::kDriving, frontiers({{9, 9}}));
  ASSERT_TRUE(t);
  EXPECT_EQ(t->activity, RobotActivity::kGoingHome);
  EXPECT_EQ(t->position_m, Eigen::Vector2d::Zero());
  b.on_base_goal({8, GoalKind::kExplore, true, {6, 2}}, at(3), kHere);  // ignored
  EXPECT_FALSE(b.update(at(3), kFar, NavState::kDriving, frontiers({{9, 9}})));
  EXPECT_EQ(b.activity(), RobotActivity::kGoingHome);
  EXPECT_FALSE(b.update(at(9), Eigen::Vector2d(0.5, 0), NavState::kReached, frontiers({{9, 9}})));
  EXPECT_TRUE(b.done());
  b.on_base_goal({9, GoalKind::kExplore, true, {6, 2}}, at(10), kHere);  // still ignored: it stays home
  EXPECT_FALSE(b.update(at(10), Eigen::Vector2d(0.5, 0), NavState::kIdle, frontiers({{9, 9}})));
  EXPECT_TRUE(b.done());
}

}  // namespace
}  // namespace cairn::agent
