#include "sim/diff_drive.h"

#include <gtest/gtest.h>

namespace cairn::sim {
namespace {

TEST(WaypointFollower, ReachesWaypointsAndStops) {
  const std::vector<Eigen::Vector2d> wps = {{3, 0}, {3, 2}, {0, 2}};
  FollowerOptions options;
  WaypointFollower follower(Eigen::Vector2d(0, 0), wps, options);
  SE2 pose(0, 0, M_PI);  // starts facing away: must turn first
  size_t reached_second_at = 0;
  for (int k = 0; k < 2000 && !follower.finished(); ++k) {
    const VelocityCommand cmd = follower.update(pose);
    EXPECT_LE(std::abs(cmd.linear_mps), options.max_speed_mps + 1e-9);
    EXPECT_LE(std::abs(cmd.angular_radps), options.max_turn_radps + 1e-9);
    pose = integrate_unicycle(pose, cmd.linear_mps, cmd.angular_radps, 0.05);
    if (follower.next_waypoint() >= 2 && reached_second_at == 0) reached_second_at = size_t(k);
  }
  ASSERT_TRUE(follower.finished());
  EXPECT_GT(reached_second_at, 0u);
  EXPECT_LT((pose.translation() - wps.back()).norm(), options.waypoint_tolerance_m + 1e-9);
  const VelocityCommand stop = follower.update(pose);
  EXPECT_EQ(stop.linear_mps, 0.0);
  EXPECT_EQ(stop.angular_radps, 0.0);
}

TEST(IntegrateUnicycle, ArcIsExact) {
  // A quarter circle of radius 1: v = 1, w = 1 for pi/2 seconds.
  const SE2 end = integrate_unicycle(SE2(), 1.0, 1.0, M_PI / 2);
  EXPECT_NEAR(end.x(), 1.0, 1e-12);
  EXPECT_NEAR(end.y(), 1.0, 1e-12);
  EXPECT_NEAR(end.yaw(), M_PI / 2, 1e-12);
}

// Drives a square loop and returns the final odometry error against the truth.
double odometry_error(double scale, uint64_t seed) {
  OdometryOptions noise;
  noise.trans_noise_per_m = 0.05 * scale;
  noise.rot_noise_rad_per_m = 0.02 * scale;
  noise.rot_noise_per_rad = 0.05 * scale;
  OdometryIntegrator odom(noise, seed);
  SE2 truth;
  for (int k = 0; k < 800; ++k) {
    const double w = (k % 200) >= 180 ? M_PI / 2 : 0.0;  // straight 9 m, then turn 90 deg in 1 s
    const SE2 next = integrate_unicycle(truth, w == 0.0 ? 0.5 : 0.0, w, 0.05);
    odom.add_step(truth.between(next), 0.05);
    truth = next;
  }
  return (odom.T_odom_base().translation() - truth.translation()).norm() +
         std::abs(normalize_angle(odom.T_odom_base().yaw() - truth.yaw()));
}

TEST(OdometryIntegrator, ZeroNoiseIsExactAndDriftGrowsWithNoise) {
  EXPECT_NEAR(odometry_error(0.0, 1), 0.0, 1e-9);
  double low = 0, high = 0;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    low += odometry_error(0.2, seed);
    high += odometry_error(2.0, seed);
  }
  EXPECT_GT(low, 0.0);
  EXPECT_GT(high, 3.0 * low);
}

}  // namespace
}  // namespace cairn::sim
