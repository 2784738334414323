// Frontier exploration on hand-drawn grids: robots go to the nearest distinct frontier along free
// space, a frontier near a victim wins a tie, walls count in the path, closed rooms and crumbs of
// frontier give no goals.
#include "base_station/core/exploration.h"

#include <gtest/gtest.h>

#include "base_station/core/saliency_layer.h"
#include "common/grid_drawing_test_util.h"

namespace cairn::base {
namespace {

constexpr double kRes = 0.1;

/// A 12 m x 6 m grid at 0.1 m, all unknown (common/grid_drawing_test_util.h).
struct Drawing : testing::GridDrawing {
  Drawing() : GridDrawing(12, 6, kRes) {}
  /// A corridor from x = 1 to 11 m, 2 m wide, walls along both sides, open (unknown) at both ends.
  void corridor() {
    free(1, 2, 11, 4);
    wall(1, 1.8, 11, 2);
    wall(1, 4, 11, 4.2);
  }
};

const ExplorationGoal* goal_of(const ExplorationPlan& plan, int robot) {
  for (const auto& g : plan.goals) {
    if (g.robot.value == robot) return &g;
  }
  return nullptr;
}

TEST(Exploration, EachRobotTakesTheNearestFrontierOfItsOwn) {
  Drawing d;
  d.corridor();
  const ExplorationPlan plan = plan_exploration(d.grid, {{RobotId(0), {3, 3}}, {RobotId(1), {9, 3}}}, {});
  ASSERT_EQ(plan.frontiers.size(), 2u);
  const ExplorationGoal* west = goal_of(plan, 0);
  const ExplorationGoal* east = goal_of(plan, 1);
  ASSERT_TRUE(west && east);
  EXPECT_LT(west->goal_m.x(), 1.5);
  EXPECT_GT(east->goal_m.x(), 10.5);
  EXPECT_NEAR(west->path_m, 2.0, 0.3);  // 3 m -> the frontier column at ~1 m
  EXPECT_TRUE(plan.idle.empty());

  // Swapped starts: swapped goals.
  const ExplorationPlan swapped = plan_exploration(d.grid, {{RobotId(0), {9, 3}}, {RobotId(1), {3, 3}}}, {});
  EXPECT_GT(goal_of(swapped, 0)->goal_m.x(), 10.5);
  EXPECT_LT(goal_of(swapped, 1)->goal_m.x(), 1.5);
}

TEST(Exploration, OneFrontierGoesToTheNearerRobotAndTheOtherSharesItRatherThanStandIdle) {
  Drawing d;
  d.corridor();
  d.wall(10.8, 2, 11, 4);  // the east end closed
  ExplorationOptions strict;
  strict.share_when_crowded = false;
  const ExplorationPlan plan = plan_exploration(d.grid, {{RobotId(0), {3, 3}}, {RobotId(1), {9, 3}}}, {}, strict);
  ASSERT_EQ(plan.frontiers.size(), 1u);
  ASSERT_EQ(plan.goals.size(), 1u);
  EXPECT_EQ(plan.goals[0].robot, RobotId(0));  // nearer
  ASSERT_EQ(plan.idle.size(), 1u);
  EXPECT_EQ(plan.idle[0], RobotId(1));
  const ExplorationPlan shared = plan_exploration(d.grid, {{RobotId(0), {3, 3}}, {RobotId(1), {9, 3}}}, {});
  ASSERT_EQ(shared.goals.size(), 2u);
  EXPECT_EQ(shared.goals[0].robot, RobotId(0));
  EXPECT_EQ(shared.goals[1].frontier, shared.goals[0].frontier);
  EXPECT_TRUE(shared.idle.empty());
}

TEST(Exploration, UncoordinatedRobotsBothTakeTheNearestFrontier) {
  Drawing d;
  d.corridor();  // frontiers at both ends: x = 1 and x = 11
  ExplorationOptions o;
  o.coordination = ExplorationOptions::Coordination::kNearestFrontier;
  // Both robots are nearer the west end: uncoordinated, both go there; coordinated, one goes east.
  const std::map<RobotId, Eigen::Vector2d> robots{{RobotId(0), {3, 3}}, {RobotId(1), {4, 3}}};
  const ExplorationPlan alone = plan_exploration(d.grid, robots, {}, o);
  ASSERT_EQ(alone.goals.size(), 2u);
  EXPECT_LT(goal_of(alone, 0)->goal_m.x(), 1.5);
  EXPECT_LT(goal_of(alone, 1)->goal_m.x(), 1.5);
  const ExplorationPlan together = plan_exploration(d.grid, robots, {});
  ASSERT_EQ(together.goals.size(), 2u);
  EXPECT_GT(std::max(goal_of(together, 0)->goal_m.x(), goal_of(together, 1)->goal_m.x()), 10.5);
}

TEST(Exploration, ABlacklistedGoalIsNotOfferedAgainAndTheCurrentGoalIsKept) {
  Drawing d;
  d.corridor();
  const std::map<RobotId, Eigen::Vector2d> robot{{RobotId(0), {5, 3}}};
  const ExplorationPlan first = plan_exploration(d.grid, robot, {});
  ASSERT_EQ(first.goals.size(), 1u);
  const Eigen::Vector2d west = first.goals[0].goal_m;
  EXPECT_LT(west.x(), 1.5) << "the nearer end";
  ExplorationContext failed;
  failed.blacklist_m = {{1.0, 2.5}, {1.0, 3.5}};
  const ExplorationPlan next = plan_exploration(d.grid, robot, {}, {}, failed);
  ASSERT_EQ(next.goals.size(), 1u);
  EXPECT_GT(next.goals[0].goal_m.x(), 10.5) << "the west end failed: the east one";
  // Slightly nearer the east end now, the robot keeps driving west (hysteresis)...
  const std::map<RobotId, Eigen::Vector2d> moved{{RobotId(0), {6.2, 3}}};
  ExplorationContext driving;
  driving.current_goals_m[RobotId(0)] = west;
  EXPECT_LT(plan_exploration(d.grid, moved, {}, {}, driving).goals[0].goal_m.x(), 1.5);
  // ...which it would not without a current goal.
  EXPECT_GT(plan_exploration(d.grid, moved, {}, {}).goals[0].goal_m.x(), 10.5);
}

TEST(Exploration, AKeepOutAreaHoldsNoGoalAndNoPathCrossesIt) {
  Drawing d;
  d.corridor();
  const std::map<RobotId, Eigen::Vector2d> robot = {{RobotId(0), {3, 3}}};
  ASSERT_LT(plan_exploration(d.grid, robot, {}).goals[0].goal_m.x(), 1.5);  // west, the nearer end
  // The operator closes the west end: the robot is sent east instead.
  ExplorationContext west_closed;
  west_closed.keep_out.push_back({1, {0, 1}, {1.6, 5}});
  const ExplorationPlan east = plan_exploration(d.grid, robot, {}, {}, west_closed);
  ASSERT_EQ(east.goals.size(), 1u);
  EXPECT_GT(east.goals[0].goal_m.x(), 10.5);
  // An area across the corridor between the robot and the east end: it cannot get past it there.
  ExplorationContext barrier = west_closed;
  barrier.keep_out.push_back({2, {6, 1.5}, {7, 4.5}});
  const ExplorationPlan none = plan_exploration(d.grid, robot, {}, {}, barrier);
  EXPECT_TRUE(none.goals.empty());
  EXPECT_EQ(none.idle, std::vector<RobotId>{RobotId(0)});
}

TEST(Exploration, AClosedRoomLeavesNothingToExplore) {
  Drawing d;
  d.corridor();
  d.wall(1, 2, 1.2, 4);
  d.wall(10.8, 2, 11, 4);
  const ExplorationPlan plan = plan_exploration(d.grid, {{RobotId(0), {5, 3}}}, {});
  EXPECT_TRUE(plan.frontiers.empty());
  EXPECT_TRUE(plan.goals.empty());
  EXPECT_EQ(plan.idle.size(), 1u);
}

TEST(Exploration, AVictimNearAFrontierDrawsTheRobotThere) {
  Drawing d;
  d.corridor();
  const ExplorationPlan west = plan_exploration(d.grid, {{RobotId(0), {6, 3}}}, {{1.5, 3}});
  ASSERT_EQ(west.goals.size(), 1u);
  EXPECT_LT(west.goals[0].goal_m.x(), 1.5);
  const ExplorationPlan east = plan_exploration(d.grid, {{RobotId(0), {6, 3}}}, {{10.5, 3}});
  ASSERT_EQ(east.goals.size(), 1u);
  EXPECT_GT(east.goals[0].goal_m.x(), 10.5);
}

TEST(Exploration, ASalientOpeningDrawsTheRobotThereWhenSaliencyCounts) {
  Drawing d;
  d.corridor();
  // Something colourful seen beyond the east end (x 12 m), nothing in the west; the robot slightly
  // nearer the west end.
  SaliencyLayer layer({0, 0}, {12, 6}, 0.25);
  layer.raise({11.8, 3}, 0.9);
  ExplorationContext context;
  context.saliency = &layer;
  ExplorationOptions attentive;
  attentive.saliency_weight = 3.0;
  const std::map<RobotId, Eigen::Vector2d> robot{{RobotId(0), {5.5, 3}}};
  const ExplorationPlan drawn = plan_exploration(d.grid, robot, {}, attentive, context);
  ASSERT_EQ(drawn.goals.size(), 1u);
  EXPECT_GT(drawn.goals[0].goal_m.x(), 10.5);
  const Frontier& east = drawn.frontiers[size_t(drawn.goals[0].frontier)];
  EXPECT_NEAR(east.saliency, 0.9, 1e-6);
  EXPECT_NEAR(east.weight, 1.0 + 3.0 * 0.9, 1e-6);
  // Without the weight (the coordinated strategy alone) the layer is ignored: the nearer west end.
  const ExplorationPlan plain = plan_exploration(d.grid, robot, {}, ExplorationOptions{}, context);
  ASSERT_EQ(plain.goals.size(), 1u);
  EXPECT_LT(plain.goals[0].goal_m.x(), 1.5);
}

TEST(Exploration, PathsGoAroundWalls) {
  Drawing d;
  // Two rooms side by side joined by a door at the top; the frontier is in the east room's floor
  // (open to the south), the robot in the west room right behind the dividing wall.
  d.free(1, 1, 11, 5);
  d.wall(1, 5, 11, 5.2);     // north wall
  d.wall(0.8, 1, 1, 5.2);    // west wall
  d.wall(10.8, 1, 11, 5.2);  // east wall
  d.wall(1, 0.8, 6, 1);      // south wall of the west room only: the east room opens south
  d.wall(6, 1, 6.2, 4);      // the dividing wall, door from y = 4 to 5
  const ExplorationPlan plan = plan_exploration(d.grid, {{RobotId(0), {5.5, 1.5}}}, {});
  ASSERT_EQ(plan.goals.size(), 1u);
  const ExplorationGoal& g = plan.goals[0];
  EXPECT_GT(g.goal_m.x(), 6.2);
  EXPECT_LT(g.goal_m.y(), 1.2);
  // Straight line ~0.9 m; through the door at least 2 x 2.5 m.
  EXPECT_GT(g.path_m, 5.0);
}

TEST(Exploration, CrumbsOfFrontierAreIgnored) {
  Drawing d;
  d.corridor();
  d.wall(1, 2, 1.2, 4);
  d.wall(10.8, 2, 11, 4);
  d.paint(5, 3, 5.2, 3.2, 0.f);  // one unknown cell inside the room: its 4 neighbours are frontier
  ExplorationOptions o;
  o.min_frontier_cells = 10;
  EXPECT_TRUE(plan_exploration(d.grid, {{RobotId(0), {3, 3}}}, {}, o).frontiers.empty());
  o.min_frontier_cells = 4;
  EXPECT_EQ(plan_exploration(d.grid, {{RobotId(0), {3, 3}}}, {}, o).frontiers.size(), 1u);
}

}  // namespace
}  // namespace cairn::base
