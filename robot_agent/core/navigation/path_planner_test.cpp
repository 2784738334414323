// The planner on drawn grids (0.1 m cells, a 0.2 m robot): around a wall, never within the
// robot's radius of a wall, through a 0.6 m door but not a 0.3 m one, a blocked corridor refused
// with its reason, a goal in a wall moved to free space, unknown space crossed only at a cost, and
// a robot boxed in told apart from a goal that cannot be reached, and the operator's keep-out
// areas (turned into the robot's frame) never crossed, except the one the robot stands in.
#include "robot_agent/core/navigation/path_planner.h"

#include <gtest/gtest.h>

#include <cmath>

#include "robot_agent/core/navigation/nav_test_util.h"

namespace cairn::agent {
namespace {

using testing::GridDrawing;

/// A closed room [1, 9] x [1, 5] with walls 0.1 m thick outside it.
GridDrawing room() {
  GridDrawing d;
  d.room();
  return d;
}

/// Distance from p to the nearest occupied cell's square (not its centre).
double distance_to_occupied(const OccupancyGrid& grid, const Eigen::Vector2d& p) {
  double best = 1e9;
  const double half = 0.5 * grid.resolution_m();
  for (int r = 0; r < grid.height(); ++r) {
    for (int c = 0; c < grid.width(); ++c) {
      if (grid.probability(c, r) <= 0.65) continue;
      const Eigen::Vector2d d = ((p - grid.cell_center_m(c, r)).cwiseAbs().array() - half).cwiseMax(0.0).matrix();
      best = std::min(best, d.norm());
    }
  }
  return best;
}

double polyline_length(const std::vector<Eigen::Vector2d>& path) {
  double length = 0;
  for (size_t i = 1; i < path.size(); ++i) length += (path[i] - path[i - 1]).norm();
  return length;
}

TEST(PathPlanner, GoesAroundAWallKeepingTheRobotsRadiusFromIt) {
  GridDrawing d = room();
  d.wall(5, 1, 5.1, 4);  // a dividing wall, 1 m passage at the north end
  const PathPlanner planner;
  const PlannedPath p = planner.plan(d.grid, {3, 2}, {7, 2}, 0.4);
  ASSERT_TRUE(p.ok()) << p.reason;
  EXPECT_TRUE(p.reason.empty());
  EXPECT_TRUE(p.path_m.front().isApprox(Eigen::Vector2d(3, 2)));
  EXPECT_TRUE(p.path_m.back().isApprox(Eigen::Vector2d(7, 2)));
  // Up to the passage (y > 4) and down again: more than twice the 2.9 m from either end to the
  // wall's top, where the straight line is 4 m.
  EXPECT_GT(polyline_length(p.path_m), 5.8);
  EXPECT_LT(polyline_length(p.path_m), 9.0);
  double top = 0, nearest = 1e9;
  for (const Eigen::Vector2d& q : p.path_m) {
    top = std::max(top, q.y());
    nearest = std::min(nearest, distance_to_occupied(d.grid, q));
  }
  EXPECT_GT(top, 4.0);
  EXPECT_GE(nearest, 0.2);  // the robot's radius from every wall's surface
  EXPECT_LT(nearest, 0.5);  // (it does use the passage next to the wall's end)
}

TEST(PathPlanner, GoesAroundAKeepOutAreaTurnedIntoItsFrameAndNeverThroughIt) {
  GridDrawing d = room();
  // The operator's rectangle as the robot sees it in its own frame: turned (0.2 rad), across the
  // middle of the room, open at the north end. (keep_out_test checks the turning into its frame.)
  const KeepOutPolygon turned = in_frame({4, {0, 0}, {0.6, 3.2}}, SE2(5.0, 1.0, 0.2));
  const KeepOutPolygon local = in_frame({4, {0, 0}, {0.6, 3.2}}, SE2(5.0, 1.0, 0.0));
  const PathPlanner planner;
  const PlannedPath straight = planner.plan(d.grid, {3, 2}, {7, 2}, 0.4);
  ASSERT_TRUE(straight.ok()) << straight.reason;
  EXPECT_LT(polyline_length(straight.path_m), 4.5);  // without the area: straight across
  for (const KeepOutPolygon& keep_out : {local, turned}) {
    const PlannedPath p = planner.plan(d.grid, {3, 2}, {7, 2}, 0.4, {keep_out});
    ASSERT_TRUE(p.ok()) << p.reason;
    EXPECT_GT(polyline_length(p.path_m), 5.0);  // round its north end
    for (const Eigen::Vector2d& q : p.path_m) EXPECT_FALSE(keep_out.contains(q)) << q.transpose();
  }
  // A goal inside the area is refused, naming it; a robot standing in it may drive out.
  const PlannedPath into = planner.plan(d.grid, {3, 2}, {5.3, 2}, 0.4, {local});
  EXPECT_EQ(into.status, PlanStatus::kGoalKeptOut);
  EXPECT_EQ(into.reason, "the goal (5.30, 2.00) lies in the operator's keep-out area 4");
  EXPECT_TRUE(planner.plan(d.grid, {5.3, 2}, {7, 2}, 0.4, {local}).ok());
}

TEST(PathPlanner, FitsThroughADoorWideEnoughAndNotThroughANarrowOne) {
  for (const auto& [door_m, fits] : std::vector<std::pair<double, bool>>{{0.6, true}, {0.3, false}}) {
    GridDrawing d = room();
    d.wall(5, 1, 5.1, 2.5);  // the dividing wall with a door at y = 2.5 .. 2.5 + door
    d.wall(5, 2.5 + door_m, 5.1, 5);
    const PlannedPath p = PathPlanner().plan(d.grid, {3, 3}, {7, 3}, 0.4);
    EXPECT_EQ(p.ok(), fits) << "door " << door_m << ": " << p.reason;
    if (fits) {
      double nearest = 1e9;
      for (const Eigen::Vector2d& q : p.path_m) nearest = std::min(nearest, distance_to_occupied(d.grid, q));
      EXPECT_GE(nearest, 0.2);
      EXPECT_LE(nearest, 0.25 + 1e-9);  // 0.6 m door: its two middle cells are 0.25 / 0.35 m from the jambs
    } else {
      EXPECT_EQ(p.status, PlanStatus::kNoPath);
      EXPECT_FALSE(p.boxed_in);       // the west room is free to drive around in
      EXPECT_GT(p.reachable_m, 2.5);  // the west room's far corner, 2.55 m away
      EXPECT_NE(p.reason.find("no path"), std::string::npos) << p.reason;
    }
  }
}

TEST(PathPlanner, ABlockedCorridorHasNoPathAndSaysWhy) {
  GridDrawing d;
  d.free(1, 2, 9, 3);  // a corridor 1 m wide, closed all round, rubble across it at x = 6
  d.wall(0.9, 1.9, 9.1, 2);
  d.wall(0.9, 3, 9.1, 3.1);
  d.wall(0.9, 1.9, 1, 3.1);
  d.wall(9, 1.9, 9.1, 3.1);
  d.wall(6, 2, 6.2, 3);
  const PlannedPath p = PathPlanner().plan(d.grid, {2, 2.5}, {8, 2.5}, 0.4);
  EXPECT_EQ(p.status, PlanStatus::kNoPath);
  EXPECT_TRUE(p.path_m.empty());
  EXPECT_FALSE(p.boxed_in);
  EXPECT_NEAR(p.reachable_m, 3.7, 0.05);  // up the corridor to x = 5.75, 0.3 m short of the rubble
  EXPECT_NE(p.reason.find("no path from (2.00, 2.50) to (8.00, 2.50)"), std::string::npos) << p.reason;
  d.free(6, 2, 6.2, 3);  // cleared: a path
  EXPECT_TRUE(PathPlanner().plan(d.grid, {2, 2.5}, {8, 2.5}, 0.4).ok());
}

TEST(PathPlanner, WithNoWayToTheGoalItSettlesForTheReachableCellNearestItWhenNearEnough) {
  GridDrawing d;
  d.free(1, 2, 9, 3);  // the closed corridor of the test above, rubble across it at x = 6
  d.wall(0.9, 1.9, 9.1, 2);
  d.wall(0.9, 3, 9.1, 3.1);
  d.wall(0.9, 1.9, 1, 3.1);
  d.wall(9, 1.9, 9.1, 3.1);
  d.wall(6, 2, 6.2, 3);
  const PlannedPath p = PathPlanner().plan(d.grid, {2, 2.5}, {8, 2.5}, 0.4, {}, 3.0);
  ASSERT_TRUE(p.ok()) << p.reason;
  EXPECT_TRUE(p.settled);
  EXPECT_NEAR(p.goal_m.x(), 5.65, 0.11);  // the last cell 0.28 m clear of the rubble
  EXPECT_NEAR(p.goal_m.y(), 2.5, 0.11);
  EXPECT_TRUE(p.path_m.back().isApprox(p.goal_m));
  // Farther than settle_within_m: no path, as without it.
  EXPECT_EQ(PathPlanner().plan(d.grid, {2, 2.5}, {8, 2.5}, 0.4, {}, 2.0).status, PlanStatus::kNoPath);
  // A reachable goal is planned to as asked.
  const PlannedPath q = PathPlanner().plan(d.grid, {2, 2.5}, {4, 2.5}, 0.4, {}, 3.0);
  ASSERT_TRUE(q.ok());
  EXPECT_FALSE(q.settled);
}

TEST(PathPlanner, AGoalInAWallIsMovedToTheNearestFreeCellWithinTheTolerance) {
  const GridDrawing d = room();
  const Eigen::Vector2d goal(8.95, 3.05);  // in the band along the east wall (cells at x = 9.05)
  const PlannedPath p = PathPlanner().plan(d.grid, {3, 3}, goal, 0.4);
  ASSERT_TRUE(p.ok()) << p.reason;
  EXPECT_NEAR(p.goal_m.x(), 8.75, 1e-9);  // the first cell more than 0.28 m from the wall cells
  EXPECT_NEAR(p.goal_m.y(), 3.05, 1e-9);
  EXPECT_TRUE(p.path_m.back().isApprox(p.goal_m));
  const PlannedPath tight = PathPlanner().plan(d.grid, {3, 3}, goal, 0.15);
  EXPECT_EQ(tight.status, PlanStatus::kGoalBlocked);
  EXPECT_NE(tight.reason.find("no free cell is within 0.15 m"), std::string::npos) << tight.reason;
}

TEST(PathPlanner, CrossesUnknownSpaceOnlyAtItsCost) {
  GridDrawing d(14, 6);
  d.free(1, 1, 6, 5);  // a room seen, its east side open to unknown
  d.wall(0.9, 0.9, 6, 1);
  d.wall(0.9, 5, 6, 5.1);
  d.wall(0.9, 0.9, 1, 5.1);
  const Eigen::Vector2d from(2, 3), goal(10, 3);  // 4 m into unknown space
  const PlannedPath p = PathPlanner().plan(d.grid, from, goal, 0.4);
  ASSERT_TRUE(p.ok()) << p.reason;
  EXPECT_NEAR(p.length_m, 4.0 + 3.0 * 4.0, 0.31);  // 4 m known free + 4 m unknown at 3x
  PathPlannerOptions known_only;
  known_only.unknown_cost = 0;
  const PlannedPath q = PathPlanner(known_only).plan(d.grid, from, goal, 0.4);
  EXPECT_EQ(q.status, PlanStatus::kGoalBlocked);  // an unknown goal cell is not traversable
}

TEST(PathPlanner, AGoalFarOutsideTheMapIsRefusedWithoutPlanningOutThere) {
  const GridDrawing d = room();                                                // a 10 m x 6 m map
  const PlannedPath far = PathPlanner().plan(d.grid, {3, 3}, {5000, 3}, 0.4);  // 2.5 G cells if planned
  EXPECT_EQ(far.status, PlanStatus::kGoalOutsideMap);
  EXPECT_NE(far.reason.find("outside the map (at most 30.00 m)"), std::string::npos) << far.reason;
  const PlannedPath nan = PathPlanner().plan(d.grid, {3, 3}, {std::nan(""), 3}, 0.4);
  EXPECT_EQ(nan.status, PlanStatus::kGoalOutsideMap);
  // Just outside: planned through unknown space as before (the room is closed: no path).
  EXPECT_EQ(PathPlanner().plan(d.grid, {3, 3}, {14, 3}, 0.4).status, PlanStatus::kNoPath);
  // 25 m out, where the team's map may reach beyond this robot's own: planned too.
  EXPECT_EQ(PathPlanner().plan(d.grid, {3, 3}, {35, 3}, 0.4).status, PlanStatus::kNoPath);
}

TEST(PathPlanner, ARobotBoxedInIsToldApartFromAnUnreachableGoal) {
  GridDrawing d = room();
  d.wall(2.6, 2.6, 3.4, 2.7);  // a 0.8 m box of rubble round the robot at (3, 3)
  d.wall(2.6, 3.3, 3.4, 3.4);
  d.wall(2.6, 2.6, 2.7, 3.4);
  d.wall(3.3, 2.6, 3.4, 3.4);
  const PlannedPath p = PathPlanner().plan(d.grid, {3, 3}, {7, 3}, 0.4);
  EXPECT_FALSE(p.ok());
  EXPECT_TRUE(p.boxed_in);
  EXPECT_LT(p.reachable_m, 0.3);
  EXPECT_EQ(p.reason.rfind("boxed in", 0), 0u) << p.reason;
  // Rubble pressing on the robot (a 0.2 m hole in a 1.4 m heap): no free cell within 0.5 m.
  GridDrawing tight = room();
  tight.wall(2.3, 2.3, 3.7, 3.7);
  tight.free(2.9, 2.9, 3.1, 3.1);
  const PlannedPath t = PathPlanner().plan(tight.grid, {3, 3}, {7, 3}, 0.4);
  EXPECT_EQ(t.status, PlanStatus::kStartBlocked);
  EXPECT_TRUE(t.boxed_in);
}

}  // namespace
}  // namespace cairn::agent
