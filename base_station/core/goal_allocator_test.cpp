#include "base_station/core/goal_allocator.h"

#include <gtest/gtest.h>

namespace cairn::base {
namespace {

StampNs at(double s) { return sec_to_ns(s); }

ExplorationPlan plan_with(std::vector<std::pair<RobotId, Eigen::Vector2d>> goals) {
  ExplorationPlan plan;
  for (const auto& [robot, goal] : goals) {
    plan.frontiers.push_back({goal, 20, 1.0, 1.0});
    plan.goals.push_back({robot, int(plan.frontiers.size()) - 1, goal, 3.0, 0.25});
  }
  return plan;
}

/// The plan when none of `robots` can reach a frontier any more.
ExplorationPlan no_frontier_for(std::vector<RobotId> robots) {
  ExplorationPlan plan;
  plan.idle = std::move(robots);
  return plan;
}

const RobotId kA(0), kB(1), kC(2);

TEST(GoalAllocator, LinkedRobotsGetTheirGoalInTheirOwnFrameUnplacedOnesExploreOnTheirOwn) {
  GoalAllocator g;
  const SE2 T_b(2.0, 1.0, M_PI / 2);
  const auto orders =
      g.assign(plan_with({{kA, {5, 0}}, {kB, {2, 4}}}), {{kA, SE2()}, {kB, T_b}, {kC, std::nullopt}}, at(1));
  ASSERT_EQ(orders.size(), 3u);
  EXPECT_EQ(orders[0].kind, GoalKind::kExplore);
  EXPECT_TRUE(orders[1].goal_local_m.isApprox(Eigen::Vector2d(3, 0))) << orders[1].goal_local_m.transpose();
  EXPECT_EQ(orders[2].kind, GoalKind::kOwn);
  EXPECT_NE(orders[0].goal_id, orders[1].goal_id);
  // The same plan again changes nothing; a goal moved by less than same_goal_m keeps its id.
  EXPECT_TRUE(
      g.assign(plan_with({{kA, {5.5, 0}}, {kB, {2, 4}}}), {{kA, SE2()}, {kB, T_b}, {kC, std::nullopt}}, at(3)).empty());
  const auto moved = g.assign(plan_with({{kA, {9, 0}}, {kB, {2, 4}}}), {{kA, SE2()}, {kB, T_b}}, at(5));
  ASSERT_EQ(moved.size(), 1u);
  EXPECT_EQ(moved[0].robot, kA);
  EXPECT_GT(moved[0].goal_id, orders[2].goal_id);
}

TEST(GoalAllocator, AFailedGoalIsBlacklistedForAWhileAndReplaced) {
  GoalAllocator g;
  const auto first = g.assign(plan_with({{kA, {5, 0}}}), {{kA, SE2()}}, at(1));
  ASSERT_EQ(first.size(), 1u);
  g.report({kA, first[0].goal_id + 7, NavState::kUnreachable, RobotActivity::kExploring}, at(2));  // not ours
  EXPECT_TRUE(g.blacklist_m(at(2)).empty());
  g.report({kA, first[0].goal_id, NavState::kUnreachable, RobotActivity::kExploring}, at(2));
  g.report({kA, first[0].goal_id, NavState::kUnreachable, RobotActivity::kExploring}, at(2.5));  // repeated status
  ASSERT_EQ(g.blacklist_m(at(3)).size(), 1u);
  EXPECT_EQ(g.goals_blacklisted(), 1);
  EXPECT_TRUE(g.current_goals_m().empty());
  // The planner skips it; the next goal gets a new id.
  const auto next = g.assign(plan_with({{kA, {0, 6}}}), {{kA, SE2()}}, at(3));
  ASSERT_EQ(next.size(), 1u);
  EXPECT_GT(next[0].goal_id, first[0].goal_id);
  EXPECT_FALSE(g.blacklist_m(at(200)).empty());
  EXPECT_TRUE(g.blacklist_m(at(400)).empty()) << "the blacklist expires";
}

TEST(GoalAllocator, AReleasedRobotFreesItsGoalAndGetsAFreshOrderWhenHandedBack) {
  GoalAllocator g;
  const auto first = g.assign(plan_with({{kA, {5, 0}}}), {{kA, SE2()}}, at(1));
  ASSERT_EQ(first.size(), 1u);
  g.release(kA);  // the operator drives it
  EXPECT_TRUE(g.current_goals_m().empty());
  EXPECT_TRUE(g.orders().empty());
  // Handed back with the very same plan: a new order (a new id), not "nothing changed".
  const auto again = g.assign(plan_with({{kA, {5, 0}}}), {{kA, SE2()}}, at(2));
  ASSERT_EQ(again.size(), 1u);
  EXPECT_GT(again[0].goal_id, first[0].goal_id);
}

TEST(GoalAllocator, NoReachableFrontierSendsEveryPlacedRobotHomeOnce) {
  GoalAllocator g;
  const SE2 T_b(4.0, 0.0, 0.0);
  // A frontier for robot A only: B explores its own map meanwhile.
  const auto first = g.assign(plan_with({{kA, {5, 0}}}), {{kA, SE2()}, {kB, T_b}}, at(1));
  EXPECT_FALSE(g.sent_home());
  ASSERT_EQ(first.size(), 2u);
  EXPECT_EQ(first[1].kind, GoalKind::kOwn);
  const auto home = g.assign(no_frontier_for({kA, kB}), {{kA, SE2()}, {kB, T_b}, {kC, std::nullopt}}, at(9));
  EXPECT_TRUE(g.sent_home());
  ASSERT_EQ(home.size(), 3u);
  EXPECT_EQ(home[0].kind, GoalKind::kHome);
  EXPECT_EQ(home[1].kind, GoalKind::kHome);
  EXPECT_TRUE(home[1].goal_global_m.isApprox(Eigen::Vector2d(4, 0)));
  EXPECT_TRUE(home[1].goal_local_m.isZero());
  EXPECT_EQ(home[2].kind, GoalKind::kOwn) << "an unplaced robot finds its own way home";
  g.report({kA, home[0].goal_id, NavState::kReached, RobotActivity::kHome}, at(20));
  EXPECT_TRUE(g.assign(no_frontier_for({kA, kB}), {{kA, SE2()}, {kB, T_b}, {kC, std::nullopt}}, at(21)).empty());
  EXPECT_TRUE(g.blacklist_m(at(21)).empty()) << "home is never blacklisted";
  ASSERT_TRUE(g.sent_home_at_ns());
  EXPECT_EQ(*g.sent_home_at_ns(), at(9));
  // A frontier seen on the way home calls the team back out; the report keeps when it was sent home.
  g.assign(plan_with({{kA, {5, 0}}}), {{kA, SE2()}, {kB, T_b}}, at(30));
  EXPECT_FALSE(g.sent_home());
  ASSERT_TRUE(g.sent_home_at_ns());
  EXPECT_EQ(*g.sent_home_at_ns(), at(9));
}

TEST(GoalAllocator, NoPlacedRobotMeansNobodyIsSentHome) {
  GoalAllocator g;
  const auto orders = g.assign(ExplorationPlan{}, {{kA, std::nullopt}}, at(1));
  EXPECT_FALSE(g.sent_home());
  EXPECT_FALSE(g.sent_home_at_ns());
  ASSERT_EQ(orders.size(), 1u);
  EXPECT_EQ(orders[0].kind, GoalKind::kOwn);
}

TEST(GoalAllocator, APlanForNoRobotSendsNobodyHome) {
  // The only placed robot is off to a meeting, so the plan was made for nobody: not "nothing left".
  GoalAllocator g;
  const auto orders = g.assign(ExplorationPlan{}, {{kA, SE2()}, {kB, std::nullopt}}, at(1),
                               {{kA, {{3, 0}, {3, 0}}}, {kB, {{1, 0}, {-2, 0}}}});
  EXPECT_FALSE(g.sent_home());
  ASSERT_EQ(orders.size(), 2u);
  EXPECT_EQ(orders[0].kind, GoalKind::kMeet);
}

TEST(GoalAllocator, AMeetingGoalGoesToPlacedAndUnplacedRobotsAndIsResentOnlyWhenItMoves) {
  GoalAllocator g;
  const SE2 T_b(4.0, 0.0, M_PI);
  const auto first = g.assign(plan_with({{kA, {5, 0}}}), {{kA, SE2()}, {kB, T_b}, {kC, std::nullopt}}, at(1),
                              {{kB, {{2, 0}, T_b.inverse() * Eigen::Vector2d(2, 0)}}, {kC, {{9, 9}, {1, 1}}}});
  ASSERT_EQ(first.size(), 3u);
  EXPECT_EQ(first[0].kind, GoalKind::kExplore);
  EXPECT_EQ(first[1].kind, GoalKind::kMeet);
  EXPECT_TRUE(first[1].goal_local_m.isApprox(Eigen::Vector2d(2, 0))) << first[1].goal_local_m.transpose();
  EXPECT_EQ(first[2].kind, GoalKind::kMeet);
  EXPECT_TRUE(first[2].goal_local_m.isApprox(Eigen::Vector2d(1, 1)));
  // Reached: the same point is not sent again (no goal every plan); a moved one is.
  EXPECT_TRUE(g.report({kC, first[2].goal_id, NavState::kReached, RobotActivity::kMeeting}, at(2)));
  EXPECT_TRUE(g.blacklist_m(at(2)).empty()) << "a meeting point is no frontier to blacklist";
  const std::map<RobotId, std::optional<SE2>> placements{{kA, SE2()}, {kB, T_b}, {kC, std::nullopt}};
  EXPECT_TRUE(
      g.assign(plan_with({{kA, {5, 0}}}), placements, at(3), {{kB, {{2.2, 0}, {1.8, 0}}}, {kC, {{9, 9.5}, {1, 1.5}}}})
          .empty());
  const auto moved =
      g.assign(plan_with({{kA, {5, 0}}}), placements, at(5), {{kB, {{2, 0}, {2, 0}}}, {kC, {{9, 12}, {1, 4}}}});
  ASSERT_EQ(moved.size(), 1u);
  EXPECT_EQ(moved[0].robot, kC);
  // The meeting over: the placed teammate gets its frontier, the unplaced robot its own map again.
  const auto after = g.assign(plan_with({{kA, {5, 0}}, {kB, {0, 4}}}), placements, at(7));
  ASSERT_EQ(after.size(), 2u);
  EXPECT_EQ(after[0].kind, GoalKind::kExplore);
  EXPECT_EQ(after[1].kind, GoalKind::kOwn);
}

}  // namespace
}  // namespace cairn::base
