#include "common/multirobot_log.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "common/errors.h"

namespace cairn {
namespace {

MultiRobotLog parse(const std::string& text) {
  std::istringstream in(text);
  return parse_multirobot_log(in, "test.mrlog");
}

TEST(MultiRobotLog, ParsesEveryRecordType) {
  const MultiRobotLog log = parse(
      "# a comment\n\nCAIRN_MRLOG 1\nMARKER 7 3.5 -2\n"
      "ODOM 0 1.5 0.1 0.2 0.3\n"
      "SCAN 0 1.5 -1.5 0.5 10 4 1.0 inf nan 2.5\n"
      "LANDMARK 0 1.5 7 2.0 0.25 0.05 0.02\n"
      "TRUTH 0 1.5 5 6 0.1\n"
      "ODOM 3 0.5 0 0 0\n");
  ASSERT_EQ(log.robots.size(), 2u);
  const RobotLogData* r0 = log.robot(RobotId(0));
  ASSERT_NE(r0, nullptr);
  ASSERT_EQ(r0->odometry.size(), 1u);
  EXPECT_EQ(r0->odometry[0].stamp_ns, sec_to_ns(1.5));
  EXPECT_NEAR(r0->odometry[0].T_odom_base.yaw(), 0.3, 1e-12);
  ASSERT_EQ(r0->scans.size(), 1u);
  const LaserScan& s = r0->scans[0];
  EXPECT_EQ(s.ranges_m.size(), 4u);
  EXPECT_FLOAT_EQ(s.angle_min_rad, -1.5f);
  EXPECT_FLOAT_EQ(s.range_max_m, 10.f);
  EXPECT_TRUE(std::isinf(s.ranges_m[1]));
  EXPECT_TRUE(std::isnan(s.ranges_m[2]));
  EXPECT_EQ(log.stats.nan_ranges, 1);
  EXPECT_EQ(log.stats.inf_ranges, 1);
  ASSERT_EQ(r0->landmarks.size(), 1u);
  EXPECT_EQ(r0->landmarks[0].id, LandmarkId(7));
  EXPECT_DOUBLE_EQ(r0->landmarks[0].range_m, 2.0);
  EXPECT_DOUBLE_EQ(r0->landmarks[0].sigma_bearing_rad, 0.02);
  ASSERT_EQ(r0->truth.size(), 1u);
  EXPECT_DOUBLE_EQ(r0->truth[0].pose.x(), 5.0);
  ASSERT_EQ(log.markers.count(LandmarkId(7)), 1u);
  EXPECT_DOUBLE_EQ(log.markers.at(LandmarkId(7)).y(), -2.0);
  EXPECT_NE(log.robot(RobotId(3)), nullptr);
  EXPECT_EQ(log.robot(RobotId(1)), nullptr);
}

TEST(MultiRobotLog, WriteThenReadRoundTrips) {
  MultiRobotLog log;
  log.markers[LandmarkId(2)] = Eigen::Vector2d(1.25, -3.5);
  for (int robot = 0; robot < 2; ++robot) {
    RobotLogData& r = log.robot_data(RobotId(robot));
    for (int i = 0; i < 5; ++i) {
      const StampNs t = sec_to_ns(0.1 * i + 0.013 * robot);
      r.odometry.push_back({t, SE2(0.1 * i, 0.02 * robot, 0.05 * i), 0, 0});
      LaserScan s;
      s.stamp_ns = t;
      s.angle_min_rad = -3.1f;
      s.angle_increment_rad = 0.0175f;
      s.range_max_m = 12.f;
      s.ranges_m = {1.2345f, std::numeric_limits<float>::infinity(), 7.f};
      r.scans.push_back(s);
      r.landmarks.push_back(LandmarkObservation{LandmarkId(2), t, 3.25 + i, -0.5, 0.04, 0.015});
      r.truth.push_back({t, SE2(i, robot, 0.1)});
    }
  }
  std::stringstream ss;
  write_multirobot_log(ss, log, "round trip\nsecond line");
  const MultiRobotLog back = parse_multirobot_log(ss, "mem");
  ASSERT_EQ(back.robots.size(), 2u);
  for (const auto& [id, r] : log.robots) {
    const RobotLogData& b = back.robots.at(id);
    ASSERT_EQ(b.odometry.size(), r.odometry.size());
    ASSERT_EQ(b.scans.size(), r.scans.size());
    ASSERT_EQ(b.landmarks.size(), r.landmarks.size());
    ASSERT_EQ(b.truth.size(), r.truth.size());
    for (size_t i = 0; i < r.scans.size(); ++i) {
      EXPECT_EQ(b.odometry[i].stamp_ns, r.odometry[i].stamp_ns);
      EXPECT_NEAR(b.odometry[i].T_odom_base.yaw(), r.odometry[i].T_odom_base.yaw(), 1e-8);
      EXPECT_EQ(b.scans[i].ranges_m.size(), 3u);
      EXPECT_NEAR(b.scans[i].ranges_m[0], 1.2345f, 1e-4);
      EXPECT_TRUE(std::isinf(b.scans[i].ranges_m[1]));
      EXPECT_FLOAT_EQ(b.scans[i].angle_increment_rad, r.scans[i].angle_increment_rad);
      EXPECT_EQ(b.landmarks[i].id, r.landmarks[i].id);
      EXPECT_NEAR(b.landmarks[i].range_m, r.landmarks[i].range_m, 1e-8);
      EXPECT_EQ(b.landmarks[i].stamp_ns, r.landmarks[i].stamp_ns);
    }
  }
  EXPECT_NEAR(back.markers.at(LandmarkId(2)).x(), 1.25, 1e-9);
}

void expect_error(const std::string& text, const std::string& needle) {
  try {
    parse(text);
    ADD_FAILURE() << "no error for: " << needle;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << "got: " << e.what() << "\nwanted: " << needle;
  }
}

TEST(MultiRobotLog, BadInputNamesFileLineAndField) {
  const std::string h = "CAIRN_MRLOG 1\n";
  expect_error("", "test.mrlog: empty file");
  expect_error("ODOM 0 1 0 0 0\n", "test.mrlog:1: not a Cairn multi-robot log");
  expect_error("CAIRN_MRLOG 2\n", "test.mrlog:1: CAIRN_MRLOG version 2 is not supported");
  expect_error(h + "FOO 0 1\n", "test.mrlog:2: unknown record type 'FOO'");
  expect_error(h + "# c\nODOM 0 1 0 x 0\n", "test.mrlog:3: ODOM field y_m is not a number: 'x'");
  expect_error(h + "ODOM 0 1 0 0\n", "test.mrlog:2: ODOM record ends before field yaw_rad (truncated?)");
  expect_error(h + "ODOM 0 1 0 nan 0\n", "test.mrlog:2: ODOM field y_m must be finite");
  expect_error(h + "ODOM -1 1 0 0 0\n", "test.mrlog:2: ODOM field robot must be a whole number");
  expect_error(h + "ODOM 0 1 0 0 0 9\n", "test.mrlog:2: ODOM has unexpected trailing field '9'");
  expect_error(h + "ODOM 0 2 0 0 0\nODOM 0 1 0 0 0\n", "test.mrlog:3: ODOM stamp 1.000000 s is older");
  expect_error(h + "SCAN 0 1 0 0.1 10 3 1 2\n", "test.mrlog:2: SCAN record ends before field range");
  expect_error(h + "SCAN 0 1 0 0.1 10 2 1 2 3\n", "test.mrlog:2: SCAN has unexpected trailing field '3'");
  expect_error(h + "SCAN 0 1 0 0.1 -5 2 1 2\n", "SCAN field range_max_m must be > 0");
  expect_error(h + "SCAN 0 1 0 0.1 10 2 1 -inf\n", "SCAN beam 1 is -inf");
  expect_error(h + "SCAN 0 1 0 0.1 10 2.5 1 2\n", "SCAN field n must be a whole number");
  expect_error(h + "LANDMARK 0 1 3 nan 0.1 0.05 0.02\n", "test.mrlog:2: LANDMARK field range_m must be finite");
  expect_error(h + "LANDMARK 0 1 3 2 nan 0.05 0.02\n", "LANDMARK field bearing_rad must be finite");
  expect_error(h + "LANDMARK 0 1 3 2 0.1 0 0.02\n", "LANDMARK field sigma_range_m must be > 0");
  expect_error(h + "LANDMARK 0 1 3 -2 0.1 0.05 0.02\n", "LANDMARK field range_m must be >= 0");
  expect_error(h + "LANDMARK 0 1 -3 2 0.1 0.05 0.02\n", "LANDMARK field id must be a whole number");
  expect_error(h + "LANDMARK 0 nan 3 2 0.1 0.05 0.02\n", "LANDMARK field t_s must be finite");
  // Found by the sanitized fuzz run: a huge time overflowed the nanosecond stamp (UB).
  expect_error(h + "LANDMARK 0 2.2e100 3 2 0.1 0.05 0.02\n", "LANDMARK field t_s must be a time within +-9e9 s");
  expect_error(h + "ODOM 0 -1e10 0 0 0\n", "test.mrlog:2: ODOM field t_s must be a time within");
  expect_error(h + "MARKER 1 0 0\nMARKER 1 2 2\n", "test.mrlog:3: MARKER marker 1 is defined twice");
}

TEST(MultiRobotLog, FilesAndHeaderDetection) {
  const std::string path = ::testing::TempDir() + "/detect.mrlog";
  std::ofstream(path) << "# converted\n\nCAIRN_MRLOG 1\nODOM 1 0 0 0 0\n";
  EXPECT_TRUE(is_multirobot_log(path));
  EXPECT_EQ(read_multirobot_log(path).robots.size(), 1u);
  const std::string carmen = ::testing::TempDir() + "/detect.clf";
  std::ofstream(carmen) << "# CARMEN\nODOM 1 2 0 0 0 0 1 h 1\n";
  EXPECT_FALSE(is_multirobot_log(carmen));
  EXPECT_THROW(read_multirobot_log(::testing::TempDir() + "/does_not_exist.mrlog"), InputError);
}

TEST(LandmarkObservation, ValidationAndReexpression) {
  LandmarkObservation o{LandmarkId(4), 0, 2.0, 0.5, 0.05, 0.02};
  EXPECT_TRUE(validate_landmark_observation(o).empty());
  LandmarkObservation bad = o;
  bad.range_m = std::nan("");
  EXPECT_NE(validate_landmark_observation(bad), "");
  bad = o;
  bad.sigma_bearing_rad = 0;
  EXPECT_NE(validate_landmark_observation(bad), "");
  // Seen from a frame 1 m behind and turned by 0.3 rad: the world point must not move.
  const SE2 T_new_old(-1.0, 0.2, 0.3);
  const LandmarkObservation m = reexpress_landmark(o, T_new_old);
  EXPECT_LT((m.point_m() - T_new_old * o.point_m()).norm(), 1e-12);
  EXPECT_GT(m.sigma_range_m, 0.0);
  EXPECT_GE(m.sigma_bearing_rad, o.sigma_bearing_rad);
  // Identity keeps the sigmas.
  const LandmarkObservation same = reexpress_landmark(o, SE2());
  EXPECT_NEAR(same.sigma_range_m, o.sigma_range_m, 1e-9);
  EXPECT_NEAR(same.sigma_bearing_rad, o.sigma_bearing_rad, 1e-9);
}

}  // namespace
}  // namespace cairn
