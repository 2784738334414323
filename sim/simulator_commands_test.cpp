// The simulator in command mode (velocity commands, like a real robot's cmd_vel): driving, limits,
// refused commands, collisions with walls and robots, the other robots in the laser, mission end.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "sim/sim_test_util.h"
#include "sim/simulator.h"

namespace cairn::sim {
namespace {

// A 10 m x 6 m room (walls one cell thick: inner faces at x = 0.05, 9.95, y = 0.05, 5.95) with a
// pillar at x 5..5.5, y 2.5..3.5, and robots without routes at the given start poses (ids 0, 1, ...).
World room(const std::vector<SE2>& starts) {
  World world;
  world.name = "room";
  world.floor_plan = testing::room_with_pillar();
  for (size_t i = 0; i < starts.size(); ++i) {
    RobotSpec r;
    r.id = RobotId(int(i));
    r.T_world_start = starts[i];
    world.robots.push_back(r);
  }
  return world;
}

SimOptions options_without_noise() {
  SimOptions o;
  o.enable_camera = false;
  o.odometry.trans_noise_per_m = o.odometry.rot_noise_rad_per_m = o.odometry.rot_noise_per_rad = 0.0;
  return o;
}

void run_s(Simulator& sim, double seconds) {
  const int steps = int(std::lround(seconds / ns_to_sec(sim.dt_ns())));
  for (int i = 0; i < steps; ++i) sim.step();
}

TEST(SimulatorCommands, RobotsStandStillUntilToldThenDriveAndTurnAsCommanded) {
  Simulator sim(room({SE2(1, 1, 0)}), options_without_noise());
  EXPECT_EQ(sim.drive_mode(), DriveMode::kCommands);
  const RobotId r(0);
  run_s(sim, 1.0);
  EXPECT_EQ(sim.true_pose(r).vector(), SE2(1, 1, 0).vector());
  ASSERT_TRUE(sim.set_command(r, {0.5, 0.0}));
  run_s(sim, 4.0);
  EXPECT_NEAR(sim.true_pose(r).x(), 3.0, 0.003);  // v * t
  EXPECT_NEAR(sim.true_pose(r).y(), 1.0, 1e-9);
  ASSERT_TRUE(sim.set_command(r, {0.0, 0.5}));
  run_s(sim, 2.0);
  EXPECT_NEAR(sim.true_pose(r).yaw(), 1.0, 1e-6);  // w * t, in place
  EXPECT_NEAR(sim.true_pose(r).x(), 3.0, 0.003);
  ASSERT_TRUE(sim.set_command(r, {0.4, 0.0}));
  run_s(sim, 2.5);  // 1 m along the new heading
  EXPECT_NEAR(sim.true_pose(r).x(), 3.0 + std::cos(1.0), 0.003);
  EXPECT_NEAR(sim.true_pose(r).y(), 1.0 + std::sin(1.0), 0.003);
  // Odometry (without noise) integrates the same motion.
  const SE2 truth = sim.T_world_start(r).between(sim.true_pose(r));
  const SimStep s = sim.step();
  ASSERT_FALSE(s.odometry.empty());
  EXPECT_NEAR((s.odometry[0].reading.T_odom_base.translation() - truth.translation()).norm(), 0.0, 1e-9);
  EXPECT_NEAR(s.odometry[0].reading.linear_mps, 0.4, 1e-9);
  EXPECT_EQ(sim.collisions(r), 0);
}

TEST(SimulatorCommands, CommandsAreClampedToTheRobotsLimits) {
  World world = room({SE2(5, 4.5, 0)});
  world.robots[0].max_speed_mps = 0.6;
  world.robots[0].max_turn_radps = 1.2;
  Simulator sim(world, options_without_noise());
  const RobotId r(0);
  ASSERT_TRUE(sim.set_command(r, {5.0, -9.0}));
  EXPECT_EQ(sim.command(r).linear_mps, 0.6);
  EXPECT_EQ(sim.command(r).angular_radps, -1.2);
  ASSERT_TRUE(sim.set_command(r, {-3.0, 0.0}));  // reverse: the same limit
  EXPECT_EQ(sim.command(r).linear_mps, -0.6);
  run_s(sim, 1.0);
  EXPECT_NEAR(sim.true_pose(r).x(), 5.0 - 0.6, 1e-9);
  ASSERT_TRUE(sim.set_command(r, {0.0, 100.0}));
  run_s(sim, 1.0);
  EXPECT_NEAR(sim.true_pose(r).yaw(), 1.2, 1e-9);
}

TEST(SimulatorCommands, NonFiniteCommandsUnknownRobotsAndWaypointModeAreRefused) {
  Simulator sim(room({SE2(1, 1, 0)}), options_without_noise());
  const RobotId r(0);
  ASSERT_TRUE(sim.set_command(r, {0.3, 0.1}));
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(sim.set_command(r, {nan, 0.0}));
  EXPECT_FALSE(sim.set_command(r, {0.0, inf}));
  EXPECT_FALSE(sim.set_command(r, {-inf, nan}));
  EXPECT_FALSE(sim.set_command(RobotId(9), {0.1, 0.0}));
  EXPECT_EQ(sim.command(r).linear_mps, 0.3);
  EXPECT_EQ(sim.command(r).angular_radps, 0.1);
  EXPECT_EQ(sim.command(RobotId(9)).linear_mps, 0.0);

  SimOptions waypoints = options_without_noise();
  waypoints.drive_mode = DriveMode::kWaypoints;
  World world = room({SE2(1, 1, 0)});
  world.robots[0].waypoints_m = {{3, 1}};
  Simulator scripted(world, waypoints);
  EXPECT_FALSE(scripted.set_command(r, {0.3, 0.0}));  // the route drives
  run_s(scripted, 2.0);
  EXPECT_GT(scripted.true_pose(r).x(), 1.5);
}

TEST(SimulatorCommands, RobotDrivenIntoAWallStopsShortOfItAndCountsOneCollisionPerContact) {
  World world = room({SE2(8, 1, 0)});
  Simulator sim(world, options_without_noise());
  const RobotId r(0);
  const FloorPlan& plan = world.floor_plan;
  ASSERT_TRUE(sim.set_command(r, {0.6, 0.0}));
  for (int i = 0; i < 200; ++i) {  // 10 s of pushing against the east wall (inner face x = 9.95)
    const SimStep s = sim.step();
    EXPECT_TRUE(plan.disc_free(sim.true_pose(r).translation(), 0.2)) << "step " << i;
    // Odometry (without noise) integrates the motion actually made: zero while blocked.
    const SE2 truth = sim.T_world_start(r).between(sim.ground_truth(r).back().pose);
    EXPECT_NEAR((s.odometry[0].reading.T_odom_base.translation() - truth.translation()).norm(), 0.0, 1e-9);
  }
  EXPECT_LT(sim.true_pose(r).x(), 9.75);
  EXPECT_GT(sim.true_pose(r).x(), 9.75 - 0.6 * 0.05);  // stopped within one step of the contact
  EXPECT_EQ(sim.collisions(r), 1);
  EXPECT_EQ(sim.step().odometry[0].reading.linear_mps, 0.0);
  // Back off, then drive into the wall again: a second contact.
  ASSERT_TRUE(sim.set_command(r, {-0.5, 0.0}));
  run_s(sim, 1.0);
  EXPECT_EQ(sim.collisions(r), 1);
  ASSERT_TRUE(sim.set_command(r, {0.5, 0.0}));
  run_s(sim, 2.0);
  EXPECT_EQ(sim.collisions(r), 2);
}

TEST(SimulatorCommands, RotationInPlaceNextToAWallIsAllowed) {
  Simulator sim(room({SE2(9.6, 1, 0)}), options_without_noise());
  const RobotId r(0);
  ASSERT_TRUE(sim.set_command(r, {0.6, 0.0}));
  run_s(sim, 1.0);
  ASSERT_EQ(sim.collisions(r), 1);
  const Eigen::Vector2d at = sim.true_pose(r).translation();
  ASSERT_TRUE(sim.set_command(r, {0.0, 1.0}));
  run_s(sim, 2.0);
  EXPECT_NEAR(sim.true_pose(r).yaw(), 2.0, 1e-9);
  EXPECT_EQ(sim.true_pose(r).translation(), at);
  EXPECT_EQ(sim.collisions(r), 1);              // turning neither ends nor starts a contact
  ASSERT_TRUE(sim.set_command(r, {0.5, 0.0}));  // now facing away from the wall
  run_s(sim, 1.0);
  EXPECT_GT((sim.true_pose(r).translation() - at).norm(), 0.45);
}

TEST(SimulatorCommands, TwoRobotsDrivenAtEachOtherStopWithoutOverlapping) {
  Simulator sim(room({SE2(2, 4.5, 0), SE2(6, 4.5, M_PI)}), options_without_noise());
  const RobotId a(0), b(1);
  ASSERT_TRUE(sim.set_command(a, {0.5, 0.0}));
  ASSERT_TRUE(sim.set_command(b, {0.5, 0.0}));
  for (int i = 0; i < 200; ++i) {
    sim.step();
    EXPECT_GE((sim.true_pose(a).translation() - sim.true_pose(b).translation()).norm(), 2 * sim.robot_radius_m())
        << "step " << i;
  }
  const double gap_m = (sim.true_pose(a).translation() - sim.true_pose(b).translation()).norm();
  EXPECT_LT(gap_m, 0.4 + 2 * 0.5 * 0.05 + 1e-9);  // they met: each stopped within one step of contact
  EXPECT_EQ(sim.collisions(a), 1);
  EXPECT_EQ(sim.collisions(b), 1);
}

TEST(SimulatorCommands, EachLaserSeesTheOtherRobotAndNotItself) {
  SimOptions options = options_without_noise();  // laser noise stays on (0.01 m)
  Simulator sim(room({SE2(2, 4.5, 0), SE2(4.5, 4.5, M_PI)}), options);
  const SimStep s = sim.step();
  ASSERT_EQ(s.scans.size(), 2u);
  for (const auto& [robot, scan] : s.scans) {
    SCOPED_TRACE(to_string(robot));
    EXPECT_NEAR(scan.ranges_m[180], 2.5 - 0.2, 0.05);  // straight ahead: the other robot's near face
    for (float r : scan.ranges_m) EXPECT_GT(r, 0.9);   // no return from its own disc (walls >= 1.1 m away)
  }
  options.lasers_see_robots = false;  // for measuring what the others cost the robots' SLAM
  Simulator blind(room({SE2(2, 4.5, 0), SE2(4.5, 4.5, M_PI)}), options);
  for (const auto& [robot, scan] : blind.step().scans) EXPECT_GT(scan.ranges_m[180], 3.0) << "through to the wall";
}

TEST(SimulatorCommands, MissionEndsAfterEveryRobotIsDeclaredDonePlusSettleOrAtTheDuration) {
  SimOptions options = options_without_noise();
  options.enable_laser = false;
  options.duration_s = 20.0;
  options.settle_time_s = 1.0;
  Simulator sim(room({SE2(2, 4.5, 0), SE2(6, 4.5, M_PI)}), options);
  run_s(sim, 2.0);
  sim.set_robot_done(RobotId(0), true);
  sim.set_robot_done(RobotId(7), true);  // unknown: ignored
  run_s(sim, 3.0);
  EXPECT_FALSE(sim.done());
  EXPECT_TRUE(sim.robot_finished(RobotId(0)));
  EXPECT_FALSE(sim.robot_finished(RobotId(1)));
  sim.set_robot_done(RobotId(1), true);
  sim.set_robot_done(RobotId(1), false);  // taken back: the settle clock stops
  run_s(sim, 2.0);
  EXPECT_FALSE(sim.done());
  sim.set_robot_done(RobotId(1), true);
  const StampNs declared_ns = sim.now_ns();
  while (!sim.done()) sim.step();
  EXPECT_EQ(sim.now_ns(), declared_ns + sec_to_ns(1.0) + sim.dt_ns());  // the first stamp after the settle time

  Simulator never_done(room({SE2(2, 4.5, 0)}), options);
  while (!never_done.done()) never_done.step();
  EXPECT_NEAR(ns_to_sec(never_done.now_ns()), 20.0, 0.051);
}

}  // namespace
}  // namespace cairn::sim
