#include "robot_agent/core/local_slam.h"

#include <gtest/gtest.h>

#include <random>

#include "robot_agent/core/test_util.h"

namespace cairn::agent {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A 4 m square loop driven in 0.1 m steps, turning 90 deg at each corner in 10 deg steps.
std::vector<SE2> square_loop() {
  std::vector<SE2> poses;
  SE2 pose(-2.0, -2.0, 0.0);
  poses.push_back(pose);
  for (int side = 0; side < 4; ++side) {
    for (int i = 0; i < 40; ++i) poses.push_back(pose = pose * SE2(0.1, 0.0, 0.0));
    for (int i = 0; i < 9; ++i) poses.push_back(pose = pose * SE2(0.0, 0.0, 10 * kDeg));
  }
  return poses;
}

TEST(LocalSlam, SquareLoopDriftsMuchLessThanOdometry) {
  const auto room = testing::make_room();
  const std::vector<SE2> truth = square_loop();
  std::mt19937 rng(7);
  std::normal_distribution<double> n01(0.0, 1.0);
  LocalSlam slam;
  SE2 odom = truth.front();
  const SE2 T_truth_local = truth.front();
  SE2 slam_pose;
  int matched = 0;
  for (size_t i = 0; i < truth.size(); ++i) {
    if (i > 0) {
      // Odometry: scale error 3 %, yaw bias 1.5 deg/m and noise.
      const SE2 d = truth[i - 1].between(truth[i]);
      const double dist = d.translation().norm();
      odom = odom * SE2(1.03 * d.x() + 0.005 * n01(rng), d.y() + 0.005 * n01(rng),
                        d.yaw() * 1.02 + 1.5 * kDeg * dist + 0.3 * kDeg * n01(rng));
    }
    const LaserScan scan = testing::ray_cast(room, truth[i], StampNs(i) * kNsPerSec / 10, 360, 0.01, unsigned(i));
    const LocalSlamResult r = slam.add_scan(scan, T_truth_local.inverse() * odom);
    if (r.status == LocalSlamResult::Status::kMatched) ++matched;
    EXPECT_NE(r.status, LocalSlamResult::Status::kMatchFailed) << "scan " << i << " " << r.match.reason;
    slam_pose = r.pose;
  }
  const SE2 slam_end = T_truth_local * slam_pose;
  const double slam_err = (slam_end.translation() - truth.back().translation()).norm();
  const double odom_err = (odom.translation() - truth.back().translation()).norm();
  EXPECT_GT(matched, int(truth.size()) / 2);
  EXPECT_GT(odom_err, 0.3);
  EXPECT_LT(slam_err, 0.05);
  EXPECT_LT(slam_err, 0.2 * odom_err);
  EXPECT_LT(std::abs(normalize_angle(slam_end.yaw() - truth.back().yaw())), 1.0 * kDeg);
  EXPECT_GE(slam.submaps().finished().size(), 1u);
}

TEST(LocalSlam, MotionFilterSkipsStationaryScansButKeepsTracking) {
  const auto room = testing::make_room();
  LocalSlam slam;
  const SE2 pose(0.5, 0.5, 0.2);
  EXPECT_EQ(slam.add_scan(testing::ray_cast(room, pose, 0), SE2()).status, LocalSlamResult::Status::kFirstScan);
  const auto r1 = slam.add_scan(testing::ray_cast(room, pose * SE2(0.01, 0, 0), kNsPerSec / 10), SE2(0.01, 0, 0));
  EXPECT_EQ(r1.status, LocalSlamResult::Status::kMotionFiltered);
  EXPECT_NEAR(r1.pose.x(), 0.01, 1e-9);
  const auto r2 = slam.add_scan(testing::ray_cast(room, pose * SE2(0.01, 0, 0), 6 * kNsPerSec), SE2(0.01, 0, 0));
  EXPECT_EQ(r2.status, LocalSlamResult::Status::kMatched);  // > 5 s: matched again
}

// Odometry that holds its reading while the robot drives on (a dead or late stream: the agent
// holds the last reading once its wait runs out) is not a standstill: the scans are skipped, also
// beyond the motion filter's max_time_s (when a scan would be matched from the held pose, metres
// off, and inserted), and the first fresh reading's step carries the pose across. A real standstill
// (the same reading, the same view) is still only motion-filtered.
TEST(LocalSlam, HeldOdometryIsNotTakenForAStandstill) {
  const auto room = testing::make_room();
  LocalSlam slam;
  std::vector<SE2> truth;
  for (int i = 0; i < 70; ++i) truth.push_back(SE2(-1.5, -1.0, 0.3) * SE2(0.04 * i, 0.0, 0.01 * i));
  SE2 held;
  for (int i = 0; i < int(truth.size()); ++i) {
    const bool dropout = i >= 20 && i < 50;  // 6 s at 5 Hz, 1.2 m driven meanwhile
    const SE2 odom = dropout ? held : truth.front().inverse() * truth[size_t(i)];
    held = odom;
    const LaserScan scan =
        testing::ray_cast(room, truth[size_t(i)], StampNs(i) * kNsPerSec / 5, 360, 0.01, unsigned(i));
    const LocalSlamResult r = slam.add_scan(scan, odom);
    if (dropout && i > 20) {  // scan 20 moved 4 cm from scan 19, where the reading was new: borderline
      EXPECT_EQ(r.status, LocalSlamResult::Status::kOdometryStalled) << "scan " << i << " " << to_string(r.status);
      EXPECT_FALSE(r.inserted) << "scan " << i;
      continue;
    }
    if (dropout) continue;
    const SE2 estimate = truth.front() * r.pose;
    EXPECT_LT((estimate.translation() - truth[size_t(i)].translation()).norm(), 0.03) << "scan " << i;
    EXPECT_LT(std::abs(normalize_angle(estimate.yaw() - truth[size_t(i)].yaw())), 0.5 * kDeg) << "scan " << i;
  }
  const SE2 odom = truth.front().inverse() * truth.back();
  const auto still = slam.add_scan(testing::ray_cast(room, truth.back(), 15 * kNsPerSec, 360, 0.01, 99), odom);
  EXPECT_EQ(still.status, LocalSlamResult::Status::kMotionFiltered);
}

TEST(LocalSlam, BadScansAreCountedNotFatal) {
  LocalSlam slam;
  LaserScan scan = testing::ray_cast(testing::make_room(), SE2(), 0);
  for (size_t i = 0; i < scan.ranges_m.size(); i += 2) scan.ranges_m[i] = std::numeric_limits<float>::quiet_NaN();
  scan.ranges_m[1] = std::numeric_limits<float>::infinity();
  scan.ranges_m[3] = 0.f;
  const auto r = slam.add_scan(scan, std::nullopt);
  EXPECT_EQ(r.filter_stats.nan_or_inf, 180);
  EXPECT_EQ(r.filter_stats.max_range, 1);  // +inf = no return
  EXPECT_EQ(r.filter_stats.too_close, 1);
  LaserScan empty = scan;
  for (float& x : empty.ranges_m) x = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(slam.add_scan(empty, std::nullopt).status, LocalSlamResult::Status::kTooFewPoints);
}

}  // namespace
}  // namespace cairn::agent
