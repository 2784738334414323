#include "sim/simulator.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "sim/ground_truth.h"
#include "sim/sim_test_util.h"

namespace cairn::sim {
namespace {

// A 10 m x 6 m room with a pillar, two robots and one object.
World small_world() {
  World world;
  world.name = "small";
  world.floor_plan = testing::room_with_pillar();
  RobotSpec a;
  a.id = RobotId(0);
  a.T_world_start = SE2(1, 1, 0);
  a.waypoints_m = {{8, 1}, {8, 4.5}};
  RobotSpec b;
  b.id = RobotId(3);
  b.T_world_start = SE2(8, 5, M_PI);
  b.waypoints_m = {{2, 5}};
  world.robots = {b, a};  // deliberately unsorted
  WorldObject o;
  o.id = 0;
  o.object_class = "victim";
  o.center_m = {9.3, 1.0, 0.25};
  world.objects = {o};
  return world;
}

SimOptions fast_options(uint64_t seed) {
  SimOptions o;
  o.seed = seed;
  o.duration_s = 30.0;
  o.drive_mode = DriveMode::kWaypoints;  // the routes of small_world()
  o.camera.width = 80;
  o.camera.height = 60;
  return o;
}

TEST(Simulator, StampsOrderAndRates) {
  Simulator sim(small_world(), fast_options(1));
  int steps = 0, odo = 0, scans = 0, frames = 0;
  while (!sim.done()) {
    const SimStep s = sim.step();
    EXPECT_EQ(s.stamp_ns, StampNs(steps) * 50'000'000);
    for (size_t i = 1; i < s.odometry.size(); ++i) EXPECT_LT(s.odometry[i - 1].robot, s.odometry[i].robot);
    for (const auto& r : s.odometry) EXPECT_EQ(r.reading.stamp_ns, s.stamp_ns);
    for (const auto& r : s.scans) EXPECT_EQ(r.reading.stamp_ns, s.stamp_ns);
    for (const auto& r : s.frames) EXPECT_TRUE(r.reading.valid());
    odo += int(s.odometry.size());
    scans += int(s.scans.size());
    frames += int(s.frames.size());
    ++steps;
  }
  EXPECT_EQ(odo, 2 * steps);                     // 20 Hz = every 50 ms step
  EXPECT_NEAR(scans, 2 * (steps + 1) / 2, 2);    // 10 Hz
  EXPECT_NEAR(frames, 2 * (steps + 9) / 10, 2);  // 2 Hz
  EXPECT_EQ(sim.ground_truth(RobotId(0)).size(), size_t(steps));
}

TEST(Simulator, ABrokenLaserFallsSilentWhileOdometryAndCameraGoOn) {
  World world = small_world();
  world.robots[0].laser_fails_at_s = 2.0;  // robot 3
  Simulator sim(world, fast_options(1));
  int robot3_scans_after = 0, robot0_scans_after = 0, robot3_odometry_after = 0, robot3_frames_after = 0;
  while (!sim.done()) {
    const SimStep s = sim.step();
    if (s.stamp_ns < 2'000'000'000) continue;
    for (const auto& r : s.scans) (r.robot == RobotId(3) ? robot3_scans_after : robot0_scans_after)++;
    for (const auto& r : s.odometry) robot3_odometry_after += r.robot == RobotId(3);
    for (const auto& r : s.frames) robot3_frames_after += r.robot == RobotId(3);
  }
  EXPECT_EQ(robot3_scans_after, 0);
  EXPECT_GT(robot0_scans_after, 50);
  EXPECT_GT(robot3_odometry_after, 100);
  EXPECT_GT(robot3_frames_after, 10);
}

TEST(Simulator, RobotsReachTheirGoalsAndTheMissionEnds) {
  Simulator sim(small_world(), fast_options(1));
  while (!sim.done()) sim.step();
  EXPECT_LT(ns_to_sec(sim.now_ns()), 30.0);  // ended by "all finished + 1 s", not by duration
  EXPECT_TRUE(sim.robot_finished(RobotId(0)));
  EXPECT_LT((sim.true_pose(RobotId(0)).translation() - Eigen::Vector2d(8, 4.5)).norm(), 0.15);
  EXPECT_LT((sim.true_pose(RobotId(3)).translation() - Eigen::Vector2d(2, 5)).norm(), 0.15);
  EXPECT_EQ(sim.T_world_start(RobotId(3)).x(), 8.0);
  EXPECT_EQ(sim.robot_ids().front(), RobotId(0));
}

TEST(Simulator, OdometryStartsAtIdentityAndFollowsTheTruthWithoutNoise) {
  SimOptions options = fast_options(1);
  options.odometry.trans_noise_per_m = options.odometry.rot_noise_rad_per_m = 0;
  options.odometry.rot_noise_per_rad = 0;
  options.enable_camera = false;
  Simulator sim(small_world(), options);
  const SimStep first = sim.step();
  ASSERT_EQ(first.odometry.size(), 2u);
  EXPECT_EQ(first.odometry[0].reading.T_odom_base.vector(), SE2().vector());
  OdometryReading last;
  for (int i = 0; i < 200; ++i) {
    const SimStep s = sim.step();
    if (!s.odometry.empty()) last = s.odometry[0].reading;
  }
  const SE2 truth = sim.T_world_start(RobotId(0)).between(sim.ground_truth(RobotId(0)).back().pose);
  EXPECT_NEAR((last.T_odom_base.translation() - truth.translation()).norm(), 0.0, 1e-9);
  EXPECT_GT(last.T_odom_base.translation().norm(), 1.0);
}

bool same(const SimStep& a, const SimStep& b) {
  if (a.odometry.size() != b.odometry.size() || a.scans.size() != b.scans.size() || a.frames.size() != b.frames.size())
    return false;
  for (size_t i = 0; i < a.odometry.size(); ++i) {
    if (a.odometry[i].reading.T_odom_base.vector() != b.odometry[i].reading.T_odom_base.vector()) return false;
  }
  for (size_t i = 0; i < a.scans.size(); ++i) {
    if (a.scans[i].reading.ranges_m != b.scans[i].reading.ranges_m) return false;
  }
  for (size_t i = 0; i < a.frames.size(); ++i) {
    if (a.frames[i].reading.depth != b.frames[i].reading.depth || a.frames[i].reading.rgb != b.frames[i].reading.rgb)
      return false;
  }
  return true;
}

TEST(Simulator, DeterministicForASeed) {
  Simulator a(small_world(), fast_options(5)), b(small_world(), fast_options(5));
  Simulator c(small_world(), fast_options(6));
  bool all_same = true, any_different = false;
  for (int i = 0; i < 100; ++i) {
    const SimStep sa = a.step(), sb = b.step(), sc = c.step();
    all_same = all_same && same(sa, sb);
    any_different = any_different || !same(sa, sc);
  }
  EXPECT_TRUE(all_same);
  EXPECT_TRUE(any_different);
}

TEST(GroundTruth, WritesTheFiles) {
  Simulator sim(small_world(), fast_options(1));
  for (int i = 0; i < 20; ++i) sim.step();
  const std::string dir =
      (std::filesystem::temp_directory_path() / ("cairn_sim_gt_test_" + std::to_string(::getpid()))).string();
  std::filesystem::remove_all(dir);
  ASSERT_TRUE(write_ground_truth(sim, dir));
  const Trajectory t = read_trajectory_csv(dir + "/gt_robot3.csv");
  EXPECT_EQ(t.size(), 20u);
  std::ifstream robots(dir + "/gt_robots.csv"), objects(dir + "/gt_objects.csv");
  std::string header, line;
  std::getline(robots, header);
  EXPECT_EQ(header, "id,start_x,start_y,start_yaw");
  std::getline(robots, line);
  EXPECT_EQ(line, "0,1,1,0");
  std::getline(objects, header);
  EXPECT_EQ(header.rfind("id,class,", 0), 0u);
  std::getline(objects, line);
  EXPECT_EQ(line.rfind("0,victim,box,9.3,1,0.25,0,", 0), 0u);
  EXPECT_FALSE(write_ground_truth(sim, "/proc/cairn_cannot_write_here"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cairn::sim
