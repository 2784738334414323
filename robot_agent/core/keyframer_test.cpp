#include "robot_agent/core/keyframer.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>

namespace cairn::agent {
namespace {

LaserScan scan_at(double t_s) {
  LaserScan s;
  s.stamp_ns = sec_to_ns(t_s);
  s.ranges_m = {1.f, 2.f};
  return s;
}

TEST(Keyframer, DistanceAngleAndTimeThresholds) {
  Keyframer kf(RobotId(3));
  const Covariance3 cov = Covariance3::Identity() * 1e-4;
  auto k0 = kf.add(scan_at(0.0), SE2(0, 0, 0), cov);
  ASSERT_TRUE(k0);
  EXPECT_EQ(k0->id, (KeyframeId{RobotId(3), 0}));
  EXPECT_FALSE(kf.add(scan_at(1.0), SE2(0.4, 0, 0), cov));
  auto k1 = kf.add(scan_at(2.0), SE2(0.6, 0, 0), cov);  // > 0.5 m
  ASSERT_TRUE(k1);
  EXPECT_EQ(k1->id.seq, 1);
  EXPECT_NEAR(k1->T_prev_this.x(), 0.6, 1e-12);
  EXPECT_EQ(k1->scan.ranges_m.size(), 2u);
  EXPECT_TRUE(k1->place_descriptor.empty());
  EXPECT_FALSE(kf.add(scan_at(3.0), SE2(0.6, 0, 0.3), cov));  // 17 deg
  auto k2 = kf.add(scan_at(3.5), SE2(0.6, 0, 0.4), cov);      // 23 deg
  ASSERT_TRUE(k2);
  EXPECT_NEAR(k2->T_prev_this.yaw(), 0.4, 1e-12);
  EXPECT_FALSE(kf.add(scan_at(8.0), SE2(0.6, 0, 0.4), cov));  // 4.5 s
  auto k3 = kf.add(scan_at(8.6), SE2(0.6, 0, 0.4), cov);      // 5.1 s
  ASSERT_TRUE(k3);
  EXPECT_EQ(k3->id.seq, 3);
  // Covariances grow along the chain and stay symmetric positive definite.
  EXPECT_GT(k3->covariance(0, 0), k1->covariance(0, 0));
  EXPECT_GT(k1->edge_covariance.llt().matrixL().determinant(), 0.0);
}

TEST(Keyframer, ADeadReckonedTurnInPlaceIsNoSurerThanAMatchedEdge) {
  // Turning in place on odometry alone: nothing driven, so the noise model gives (next to) no
  // variance along; the edge still carries the matched edges' floors (at the base, 1e-18 m^2 was
  // information 4e17 and its pose graph could not converge).
  Keyframer kf(RobotId(1));
  ASSERT_TRUE(kf.add(scan_at(0.0), SE2(1, 2, 0), Covariance3::Identity() * 1e-4));
  Covariance3 odometry = Covariance3::Zero();
  odometry(0, 0) = odometry(1, 1) = 1e-18;
  odometry(2, 2) = 1e-3;
  const auto turned = kf.add_dead_reckoned(sec_to_ns(1.0), SE2(1, 2, 0.45), odometry);
  ASSERT_TRUE(turned);
  const KeyframerOptions o;
  EXPECT_GE(turned->edge_covariance(0, 0), o.edge_translation_floor_m2);
  EXPECT_GE(turned->edge_covariance(1, 1), o.edge_translation_floor_m2);
  EXPECT_GE(turned->edge_covariance(2, 2), 1e-3 + o.edge_rotation_floor_rad2 - 1e-12);
  // Parked: no motion at all, still a finite, positive definite edge.
  const auto parked = kf.add_dead_reckoned(sec_to_ns(6.5), SE2(1, 2, 0.45), Covariance3::Zero());
  ASSERT_TRUE(parked);
  EXPECT_EQ(parked->edge_covariance.llt().info(), Eigen::Success);
  EXPECT_GE(parked->edge_covariance(0, 0), o.edge_translation_floor_m2);
}

TEST(Keyframer, ComposeCovarianceRotatesTheSecond) {
  Covariance3 b = Covariance3::Zero();
  b(0, 0) = 1.0;  // uncertain along B's x
  const Covariance3 c = compose_covariance(SE2(0, 0, M_PI / 2), Covariance3::Zero(), SE2(), b);
  EXPECT_NEAR(c(1, 1), 1.0, 1e-12);
  EXPECT_NEAR(c(0, 0), 0.0, 1e-12);
}

}  // namespace
}  // namespace cairn::agent
