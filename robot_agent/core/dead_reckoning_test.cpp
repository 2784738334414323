// DeadReckoning: poses follow the odometry increments, and the covariance it reports is the one
// the odometry noise model really produces (Monte Carlo over noisy drives).
#include "robot_agent/core/dead_reckoning.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

namespace cairn::agent {
namespace {

/// The drive: 4 m straight, a quarter turn on the spot, 2 m straight, in 5 cm / 0.05 rad steps.
std::vector<SE2> drive_steps() {
  std::vector<SE2> steps;
  for (int i = 0; i < 80; ++i) steps.push_back(SE2(0.05, 0, 0));
  for (int i = 0; i < 31; ++i) steps.push_back(SE2(0, 0, 0.05));
  for (int i = 0; i < 40; ++i) steps.push_back(SE2(0.05, 0, 0));
  return steps;
}

TEST(DeadReckoning, PosesFollowTheOdometryFromWhereTheLaserLeftTheRobot) {
  DeadReckoning dr;
  const SE2 start(2.0, 1.0, 0.5), odom_start(10.0, -3.0, 2.0);
  dr.start(start, odom_start);
  SE2 odom = odom_start;
  for (const SE2& s : drive_steps()) dr.advance(odom = odom * s);
  const SE2 expected = start * odom_start.between(odom);
  EXPECT_NEAR((dr.pose().translation() - expected.translation()).norm(), 0.0, 1e-9);
  EXPECT_NEAR(dr.pose().yaw(), expected.yaw(), 1e-9);
  EXPECT_GT(dr.covariance_since_keyframe()(0, 0), 0.0);
  dr.keyframe_emitted();
  EXPECT_EQ(dr.covariance_since_keyframe(), Covariance3::Zero());
  EXPECT_THROW(DeadReckoning(DeadReckoningOptions{0.0}), std::invalid_argument);
}

TEST(DeadReckoning, ItsCovarianceIsWhatTheOdometryNoiseProduces) {
  // Noisy odometry as the noise model says (the simulator's): per step, independent errors with
  // variance growing with the step's length and turn. The spread of the end poses over many drives
  // must match the covariance dead reckoning reports (within Monte Carlo error).
  const DeadReckoningOptions o;
  const std::vector<SE2> steps = drive_steps();
  DeadReckoning predicted(o);
  predicted.start(SE2(), SE2());
  SE2 truth;
  for (const SE2& s : steps) predicted.advance(truth = truth * s);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n01;
  const int runs = 4000;
  std::vector<Eigen::Vector3d> errors;
  for (int run = 0; run < runs; ++run) {
    SE2 noisy;
    for (const SE2& s : steps) {
      const double d = s.translation().norm(), a = std::abs(s.yaw());
      const double sd_t = std::sqrt(o.translation_variance_m2_per_m * d);
      const double sd_r = std::sqrt(o.rotation_variance_rad2_per_m * d + o.rotation_variance_rad2_per_rad * a);
      noisy = noisy * SE2(s.x() + sd_t * n01(rng), s.y() + sd_t * n01(rng), s.yaw() + sd_r * n01(rng));
    }
    // The error in the frame of the start (as the covariance is), small-angle yaw.
    errors.push_back({noisy.x() - truth.x(), noisy.y() - truth.y(), noisy.yaw() - truth.yaw()});
  }
  Eigen::Matrix3d empirical = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& e : errors) empirical += e * e.transpose() / double(runs);
  const Covariance3& c = predicted.covariance_since_keyframe();
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(empirical(i, i) / c(i, i), 1.0, 0.12)
        << "variance " << i << ": predicted " << c(i, i) << ", spread of the drives " << empirical(i, i);
  }
  // Heading error makes the lateral error: the x-yaw / y-yaw correlation is real and predicted.
  const double corr_pred = c(1, 2) / std::sqrt(c(1, 1) * c(2, 2));
  const double corr_emp = empirical(1, 2) / std::sqrt(empirical(1, 1) * empirical(2, 2));
  EXPECT_NEAR(corr_emp, corr_pred, 0.08);
}

}  // namespace
}  // namespace cairn::agent
