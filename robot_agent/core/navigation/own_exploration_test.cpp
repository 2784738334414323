// A robot out of contact explores its own map: the nearest frontier it can reach through known
// free space (by path, not in a straight line; not through a gap it does not fit), skipping failed
// goals, and nothing once the map is closed or every frontier failed.
#include "robot_agent/core/navigation/own_exploration.h"

#include <gtest/gtest.h>

#include "robot_agent/core/navigation/nav_test_util.h"

namespace cairn::agent {
namespace {

using testing::GridDrawing;

/// Two rooms [1, 5] and [5.1, 9] x [1, 5] joined by a 1 m passage at the north end of the
/// dividing wall; a 1 m opening in the west room's west wall (y 3.5-4.5) and one in the east
/// room's south wall (x 5.5-6.5), both to unknown space.
GridDrawing two_rooms() {
  GridDrawing d;
  d.room();
  d.wall(5, 1, 5.1, 4);
  d.paint(0.9, 3.5, 1, 4.5, 0.f);
  d.paint(5.5, 0.9, 6.5, 1, 0.f);
  return d;
}

TEST(OwnExploration, TakesTheNearestFrontierAlongTheWayNotInAStraightLine) {
  const GridDrawing d = two_rooms();
  const Eigen::Vector2d robot(4.5, 1.5);  // 1.6 m from the east opening in a straight line
  const std::optional<OwnFrontierGoal> g = nearest_own_frontier(d.grid, robot, {});
  ASSERT_TRUE(g);
  EXPECT_NEAR(g->goal_m.x(), 1.05, 1e-9);  // the west opening's frontier column
  EXPECT_GT(g->goal_m.y(), 3.5);
  EXPECT_LT(g->goal_m.y(), 4.5);
  EXPECT_NEAR(g->frontier_length_m, 1.0, 1e-9);
  // The west frontier's cells nearest the robot are 0.28 m inside the wall's band, so the goal is
  // one the robot can stand on; its path is ~4 m (straight: sqrt(3.45^2 + 2.35^2) = 4.2 m).
  EXPECT_GT(g->path_m, 3.5);
  EXPECT_LT(g->path_m, 6.0);
}

TEST(OwnExploration, SkipsFailedGoalsAndEndsWhenNoneIsLeft) {
  const GridDrawing d = two_rooms();
  OwnExploration explore;
  const Eigen::Vector2d robot(4.5, 1.5);
  std::optional<OwnFrontierGoal> first = nearest_own_frontier(d.grid, robot, explore.blacklisted());
  ASSERT_TRUE(first);
  explore.blacklist(first->goal_m);
  const std::optional<OwnFrontierGoal> second = nearest_own_frontier(d.grid, robot, explore.blacklisted());
  ASSERT_TRUE(second);
  EXPECT_GT(second->goal_m.x(), 5.5);  // the east room's opening, round the dividing wall
  EXPECT_NEAR(second->goal_m.y(), 1.05, 1e-9);
  EXPECT_GT(second->path_m, first->path_m);
  explore.blacklist(second->goal_m);
  EXPECT_FALSE(nearest_own_frontier(d.grid, robot, explore.blacklisted()));
  EXPECT_EQ(explore.blacklisted().size(), 2u);
  // A blacklist radius smaller than the opening leaves the rest of its frontier (of its cells only
  // y 3.75-4.25 lie outside the band the robot's radius blocks along the opening's edges, and the
  // first goal is their middle, 3.95).
  EXPECT_NEAR(first->goal_m.y(), 3.95, 1e-9);
  OwnExplorationOptions small;
  small.blacklist_radius_m = 0.15;
  const std::optional<OwnFrontierGoal> rest = nearest_own_frontier(d.grid, robot, {first->goal_m}, small);
  ASSERT_TRUE(rest);
  EXPECT_NEAR(rest->goal_m.x(), 1.05, 1e-9);
  EXPECT_GT((rest->goal_m - first->goal_m).norm(), 0.15);
}

TEST(OwnExploration, AKeepOutAreaIsNeitherExploredNorCrossed) {
  const GridDrawing d = two_rooms();
  const Eigen::Vector2d robot(4.5, 1.5);
  // The area over the west opening (the nearest frontier): the east room's opening is next.
  const KeepOutPolygon west = in_frame({9, {0.5, 3.0}, {2.0, 5.0}}, SE2());
  const std::optional<OwnFrontierGoal> g = nearest_own_frontier(d.grid, robot, {}, {}, {west});
  ASSERT_TRUE(g);
  EXPECT_GT(g->goal_m.x(), 5.5);
  // Also over the way east (the passage at the dividing wall's north end): nothing is left.
  const KeepOutPolygon passage = in_frame({10, {4.5, 3.5}, {5.6, 5.0}}, SE2());
  EXPECT_FALSE(nearest_own_frontier(d.grid, robot, {}, {}, {west, passage}));
  // A robot standing in an area is not trapped by it.
  EXPECT_TRUE(nearest_own_frontier(d.grid, robot, {}, {}, {in_frame({11, {4, 1}, {5, 2}}, SE2())}));
}

TEST(OwnExploration, AFrontierBehindAGapTooNarrowIsNotReachable) {
  GridDrawing d = two_rooms();
  d.wall(5, 4, 5.1, 4.7);    // the passage narrowed to 0.3 m: the east room is out of reach
  d.wall(0.9, 3.5, 1, 4.5);  // and the west opening closed
  EXPECT_FALSE(nearest_own_frontier(d.grid, {4.5, 1.5}, {}));
  // From inside the east room its opening is the goal.
  const std::optional<OwnFrontierGoal> g = nearest_own_frontier(d.grid, {7, 3}, {});
  ASSERT_TRUE(g);
  EXPECT_NEAR(g->goal_m.y(), 1.05, 1e-9);
}

TEST(OwnExploration, FindsTheDoorwayOfARoomItHasScanned) {
  // A 5 m x 4 m room with a 1.2 m doorway in its east wall, scanned from two poses.
  std::vector<testing::Segment> world = {{{0, 0}, {5, 0}},    {{0, 0}, {0, 4}},   {{0, 4}, {5, 4}},
                                         {{5, 0}, {5, 1.4}},  {{5, 2.6}, {5, 4}}, {{5, 1.4}, {7, 1.4}},
                                         {{5, 2.6}, {7, 2.6}}};
  NavMap map;
  for (const SE2& pose : {SE2(1.5, 2, 0), SE2(2.5, 2.5, 1.0)}) {
    for (int i = 0; i < 5; ++i) map.insert(pose, testing::ray_cast(world, pose, i));  // half a second
  }
  OwnExploration explore;
  const std::optional<OwnFrontierGoal> g = explore.next_goal(map, {1.5, 2});
  ASSERT_TRUE(g);
  // The frontier lies where the beams ended without a return: out of the doorway, past its passage
  // (the no-return beams clear 4 m), or at the edge of the cleared fan.
  EXPECT_GT(g->goal_m.x(), 4.5);
  EXPECT_GT(g->goal_m.y(), 1.4 + 0.2);
  EXPECT_LT(g->goal_m.y(), 2.6 - 0.2);
}

}  // namespace
}  // namespace cairn::agent
