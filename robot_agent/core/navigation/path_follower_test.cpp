// The follower: full speed on a clear straight path, pure pursuit's curvature on a bend, rotation
// on the spot for a path behind, slower towards the end and towards returns ahead, and a stop
// (rotation still allowed) for a return within the safety distance in the forward corridor but
// not for one beside it.
#include "robot_agent/core/navigation/path_follower.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "robot_agent/core/navigation/nav_test_util.h"

namespace cairn::agent {
namespace {

using testing::ray_cast;
using testing::Segment;

std::vector<Eigen::Vector2d> straight(double length_m) {
  std::vector<Eigen::Vector2d> path;
  for (double x = 0; x <= length_m + 1e-9; x += 0.1) path.emplace_back(x, 0);
  return path;
}

/// A scan from the origin facing +x with a 0.6 m wide obstacle across at `x_m`, centred at `y_m`.
LaserScan obstacle_at(double x_m, double y_m = 0) {
  return ray_cast({Segment{{x_m, y_m - 0.3}, {x_m, y_m + 0.3}}}, SE2(0, 0, 0), 0);
}
const LaserScan kClear = ray_cast({}, SE2(0, 0, 0), 0);

TEST(PathFollower, DrivesAClearStraightPathAtFullSpeed) {
  PathFollower f;
  f.set_path(straight(5));
  const FollowerOutput out = f.update(SE2(0, 0, 0), kClear);
  EXPECT_DOUBLE_EQ(out.command.linear_mps, 0.5);
  EXPECT_NEAR(out.command.angular_radps, 0.0, 1e-9);
  EXPECT_FALSE(out.blocked);
  EXPECT_NEAR(out.remaining_m, 5.0, 1e-6);
  EXPECT_TRUE(out.lookahead_m.isApprox(Eigen::Vector2d(0.6, 0)));
}

TEST(PathFollower, SteersThePurePursuitArc) {
  PathFollower f;
  f.set_path(straight(5));
  // 0.2 m left of the path, heading along it: the target (0.6 ahead along the path) is to the right.
  const FollowerOutput out = f.update(SE2(1, 0.2, 0), kClear);
  const Eigen::Vector2d target(1.6 - 1.0, -0.2);  // the lookahead point in the robot's frame
  EXPECT_NEAR(out.command.linear_mps, 0.5, 1e-9);
  EXPECT_NEAR(out.command.angular_radps, 0.5 * 2 * target.y() / target.squaredNorm(), 1e-6);
  EXPECT_LT(out.command.angular_radps, -0.4);
}

TEST(PathFollower, TurnsOnTheSpotForAPathBehind) {
  PathFollower f;
  f.set_path(straight(5));
  const FollowerOutput out = f.update(SE2(0, 0, 2.5), kClear);  // facing away from it
  EXPECT_EQ(out.command.linear_mps, 0.0);
  EXPECT_DOUBLE_EQ(std::abs(out.command.angular_radps), 1.0);
  EXPECT_LT(out.command.angular_radps, 0.0);  // the short way round: clockwise from 2.5 rad
}

TEST(PathFollower, SlowsTowardsTheEndAndStopsThere) {
  PathFollower f;
  f.set_path(straight(1.0));
  EXPECT_NEAR(f.update(SE2(0.5, 0, 0), kClear).command.linear_mps, 0.25, 1e-6);  // 0.5 m left of 1 m
  EXPECT_NEAR(f.update(SE2(0.9, 0, 0), kClear).command.linear_mps, 0.05, 1e-6);  // the floor
  const FollowerOutput end = f.update(SE2(0.98, 0, 0), kClear);
  EXPECT_EQ(end.command.linear_mps, 0.0);
  EXPECT_EQ(end.command.angular_radps, 0.0);
}

TEST(PathFollower, StopsForAnObstacleWithinTheSafetyDistanceAhead) {
  PathFollower f;
  f.set_path(straight(5));
  // 0.45 m ahead: 0.25 m from the robot's front edge, inside the 0.3 m safety distance.
  const FollowerOutput stop = f.update(SE2(0, 0, 0), obstacle_at(0.45));
  EXPECT_TRUE(stop.blocked);
  EXPECT_EQ(stop.command.linear_mps, 0.0);
  EXPECT_NEAR(stop.obstacle_ahead_m, 0.25, 0.01);
  // 0.6 m ahead (0.4 m from the edge): drives, slowed: (0.4 - 0.3) / (0.8 - 0.3) of full speed.
  const FollowerOutput slow = f.update(SE2(0, 0, 0), obstacle_at(0.6));
  EXPECT_FALSE(slow.blocked);
  EXPECT_NEAR(slow.command.linear_mps, 0.5 * 0.1 / 0.5, 0.01);
  // As near, but beside the corridor (the robot's 0.2 m radius + 0.05 m): no stop, full speed.
  const FollowerOutput beside = f.update(SE2(0, 0, 0), obstacle_at(0.45, 0.6));
  EXPECT_FALSE(beside.blocked);
  EXPECT_DOUBLE_EQ(beside.command.linear_mps, 0.5);
  // A path that bends away from the obstacle (its lookahead point ~0.45 rad left, the arc to it
  // cutting the corner into the obstacle) is hugged with a shorter lookahead, at the least speed.
  PathFollower bend;
  bend.set_path({{0, 0}, {0.3, 0.1}, {0.6, 0.3}, {0.8, 0.6}, {0.9, 1.0}, {0.9, 3.0}});
  const FollowerOutput hug = bend.update(SE2(0, 0, 0), obstacle_at(0.45));
  EXPECT_FALSE(hug.blocked);
  EXPECT_DOUBLE_EQ(hug.command.linear_mps, PathFollowerOptions{}.min_speed_mps);
  EXPECT_GT(hug.command.angular_radps, 0.0);
  EXPECT_NEAR(hug.heading_error_rad, 0.45, 0.02);
  // Stopped, it still turns towards the path (here one that leads into the obstacle's side).
  PathFollower into;
  into.set_path({{0, 0}, {0.4, 0.05}, {0.8, 0.3}, {1.0, 1.0}});
  const FollowerOutput turn = into.update(SE2(0, 0, 0), obstacle_at(0.3, 0.1));
  EXPECT_TRUE(turn.blocked);
  EXPECT_EQ(turn.command.linear_mps, 0.0);
  EXPECT_NEAR(turn.command.angular_radps, 2.0 * turn.heading_error_rad, 1e-9);
}

TEST(PathFollower, FreeTravelIsHowFarTheDiscDrivesOnItsArcBeforeTouchingAReturn) {
  constexpr double kRadius = 0.2;
  // Straight ahead 0.5 m: the disc's front meets it after 0.3 m (checked every 2 cm).
  EXPECT_NEAR(free_travel_m(obstacle_at(0.5), kRadius, 0.0, 1.0), 0.3, 0.021);
  constexpr double kFree = std::numeric_limits<double>::infinity();
  // Rubble along its side 0.22 m off (a robot parked beside it): never touched driving on.
  const LaserScan beside = ray_cast({Segment{{-0.2, 0.22}, {0.8, 0.22}}}, SE2(0, 0, 0), 0);
  EXPECT_EQ(free_travel_m(beside, kRadius, 0.0, 1.0), kFree);
  // Beyond what is checked: free.
  EXPECT_EQ(free_travel_m(obstacle_at(0.5), kRadius, 0.0, 0.2), kFree);
  // A stone ahead and right: met after ~0.26 m straight on, never on an arc bending left (radius
  // 0.33 m) for the 0.3 m checked.
  const LaserScan stone = ray_cast({Segment{{0.45, -0.15}, {0.45, -0.05}}}, SE2(0, 0, 0), 0);
  const double straight = free_travel_m(stone, kRadius, 0.0, 0.3);
  EXPECT_NEAR(straight, 0.26, 0.021);
  EXPECT_EQ(free_travel_m(stone, kRadius, 3.0, 0.3), kFree);
}

TEST(PathFollower, ObstacleAheadMeasuresFromTheFrontEdgeWithinTheCorridor) {
  EXPECT_NEAR(obstacle_ahead_m(obstacle_at(1.0), 0.2, 0.25), 0.8, 0.01);
  EXPECT_NEAR(obstacle_ahead_m(obstacle_at(1.0, 0.5), 0.2, 0.25), 0.8, 0.01);   // its end reaches y = 0.2
  EXPECT_TRUE(std::isinf(obstacle_ahead_m(obstacle_at(1.0, 0.6), 0.2, 0.25)));  // y from 0.3: outside
  EXPECT_TRUE(std::isinf(obstacle_ahead_m(obstacle_at(-1.0), 0.2, 0.25)));      // behind
  EXPECT_NEAR(nearest_obstacle_m(obstacle_at(-1.0), 0.2), 0.8, 0.01);
}

TEST(PathFollower, WithoutAPathItStaysStill) {
  PathFollower f;
  const FollowerOutput out = f.update(SE2(0, 0, 0), kClear);
  EXPECT_EQ(out.command.linear_mps, 0.0);
  EXPECT_EQ(out.command.angular_radps, 0.0);
}

}  // namespace
}  // namespace cairn::agent

namespace cairn::agent {
namespace {

TEST(PathFollower, EscapeHeadingPointsAwayFromTheNearestReturns) {
  // Rubble 1 cm below the disc, a wall 0.14 m above: away is up (+y), the rubble pushing hardest.
  const std::vector<Segment> pocket = {{{-1, -0.21}, {1, -0.21}}, {{-1, 0.34}, {1, 0.34}}};
  const auto away = escape_heading_rad(ray_cast(pocket, SE2(0, 0, 0), 0), 0.35);
  ASSERT_TRUE(away.has_value());
  EXPECT_NEAR(*away, M_PI / 2, 0.05);
  EXPECT_FALSE(escape_heading_rad(kClear, 0.35).has_value());
}

TEST(PathFollower, PressedAgainstRubbleItStepsAwayToTheMiddleAfterBeingBlocked) {
  // Rubble along its right side, a centimetre from the disc, and a wall 0.14 m to its left; the
  // path bends right, over the rubble's end. Blocked (no arc free), after escape_after_s it turns
  // to face away from the rubble, drives to about the middle of the strip, and no further.
  const std::vector<Segment> strip = {{{-1, -0.21}, {0.3, -0.21}}, {{0.3, -0.21}, {0.3, -1}}, {{-1, 0.34}, {2, 0.34}}};
  PathFollower f;
  f.set_path({{0, 0}, {0.3, -0.05}, {0.6, -0.4}, {0.7, -1.5}});
  SE2 pose(0, 0, 0);
  bool escaped = false;
  double min_clearance_m = 1;
  for (int i = 0; i < 200; ++i) {
    const FollowerOutput out = f.update(pose, ray_cast(strip, pose, StampNs(i) * 100'000'000));
    if (i * 0.1 < PathFollowerOptions{}.escape_after_s - 0.1) EXPECT_FALSE(out.escaping) << "at " << i * 0.1 << " s";
    if (escaped && !out.escaping) break;  // the escape is over
    escaped |= out.escaping;
    pose = testing::unicycle_step(pose, out.command, 0.1);
    min_clearance_m = std::min(min_clearance_m, testing::distance_to_walls(strip, pose.translation()) - 0.2);
  }
  ASSERT_TRUE(escaped);
  EXPECT_GT(pose.y(), 0.04);  // out of the rubble's noise, towards the middle (0.065)
  EXPECT_LT(pose.y(), 0.1);   // but not pressed against the wall instead
  EXPECT_GT(min_clearance_m, 0.0);
  std::printf("escaped to y %.3f m, least clearance %.3f m\n", pose.y(), min_clearance_m);
}

}  // namespace
}  // namespace cairn::agent

namespace cairn::agent {
namespace {

TEST(PathFollower, ThePathAheadStartsWhereTheRobotIsAndKeepsItsCorners) {
  PathFollower f;
  std::vector<Eigen::Vector2d> path;
  for (int i = 0; i <= 100; ++i) path.emplace_back(0.1 * i, 0.0);  // 10 m east in 101 points,
  for (int i = 1; i <= 50; ++i) path.emplace_back(10.0, 0.1 * i);  // then 5 m north
  f.set_path(path);
  auto ahead = f.path_ahead(32);
  ASSERT_EQ(ahead.size(), 3u);  // its start, its corner and its end
  EXPECT_TRUE(ahead[0].isApprox(path.front()));
  EXPECT_TRUE(ahead[1].isApprox(Eigen::Vector2d(10.0, 0.0)));
  EXPECT_TRUE(ahead[2].isApprox(path.back()));
  for (double x : {2.0, 4.0, 6.05}) f.update(SE2(x, 0, 0), kClear);  // 6 m along: behind it is not reported
  ahead = f.path_ahead(32);
  ASSERT_EQ(ahead.size(), 3u);
  EXPECT_NEAR(ahead.front().x(), 6.0, 1e-9);
  EXPECT_TRUE(ahead.back().isApprox(path.back()));
  f.clear();
  EXPECT_TRUE(f.path_ahead(32).empty());
}

TEST(PathFollower, APathOfMoreCornersThanReportedIsThinnedWithItsEndsKept) {
  PathFollower f;
  std::vector<Eigen::Vector2d> zigzag;  // a corner every 0.5 m, 0.5 m to either side
  for (int i = 0; i <= 80; ++i) zigzag.emplace_back(0.5 * i, i % 2 ? 0.5 : 0.0);
  f.set_path(zigzag);
  const auto ahead = f.path_ahead(32);
  ASSERT_EQ(ahead.size(), 32u);
  EXPECT_TRUE(ahead.front().isApprox(zigzag.front()));
  EXPECT_TRUE(ahead.back().isApprox(zigzag.back()));
  for (size_t i = 1; i < ahead.size(); ++i) EXPECT_GT(ahead[i].x(), ahead[i - 1].x());  // in order, no repeats
}

TEST(SimplifyPolyline, KeepsEveryPointFartherThanTheToleranceFromTheLineAndNoOther) {
  // A grid path's staircase (0.05 m cells) toward the north-east, then a real corner.
  std::vector<Eigen::Vector2d> stairs;
  for (int i = 0; i < 40; ++i) stairs.emplace_back(0.05 * ((i + 1) / 2), 0.05 * (i / 2));
  stairs.emplace_back(2.0, 0.95);  // sharp turn east
  const auto out = simplify_polyline(stairs, 0.05);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_TRUE(out.front().isApprox(stairs.front()));
  EXPECT_TRUE(out.back().isApprox(stairs.back()));
  // Every point dropped lies within the tolerance of the polyline kept.
  for (const Eigen::Vector2d& p : stairs) {
    double nearest = 1e9;
    for (size_t i = 1; i < out.size(); ++i) {
      const Eigen::Vector2d d = out[i] - out[i - 1];
      const double t = std::clamp((p - out[i - 1]).dot(d) / d.squaredNorm(), 0.0, 1.0);
      nearest = std::min(nearest, (out[i - 1] + t * d - p).norm());
    }
    EXPECT_LE(nearest, 0.05 + 1e-12);
  }
  // No tolerance: every corner stays, and only the last stair's point goes (it lies on the way east).
  EXPECT_EQ(simplify_polyline(stairs, 0.0).size(), stairs.size() - 1);
  EXPECT_EQ(simplify_polyline({{1, 2}}, 0.05).size(), 1u);
  EXPECT_TRUE(simplify_polyline({}, 0.05).empty());
}

}  // namespace
}  // namespace cairn::agent
