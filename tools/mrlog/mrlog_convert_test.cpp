#include "tools/mrlog/mrlog_convert.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "common/errors.h"

namespace cairn::mrlog {
namespace {

const std::string kWorld = std::string(CAIRN_SOURCE_DIR) + "/tools/mrlog/worlds/corridor_markers.yaml";

TEST(MrlogConvert, WorldRecordingSeesSharedMarkersAndRoundTrips) {
  WorldRecordOptions o;
  o.duration_s = 20.0;
  const MultiRobotLog log = record_world(sim::load_world_file(kWorld), o);
  ASSERT_EQ(log.robots.size(), 2u);
  EXPECT_EQ(log.markers.size(), 6u);
  std::map<RobotId, std::set<int>> seen;
  for (const auto& [id, r] : log.robots) {
    EXPECT_EQ(r.scans.size(), r.truth.size());
    EXPECT_GT(r.odometry.size(), r.scans.size());  // 20 Hz vs 10 Hz
    for (const LandmarkObservation& l : r.landmarks) {
      seen[id].insert(l.id.value);
      // The observation from the reference pose lands near the marker (noise 0.05 m, 0.02 rad).
      const SE2 T = *interpolate_pose(r.truth, l.stamp_ns);
      EXPECT_LT((T * l.point_m() - log.markers.at(l.id)).norm(), 0.35) << to_string(l.id);
    }
  }
  int shared = 0;
  for (int m : seen[RobotId(0)]) shared += seen[RobotId(1)].count(m);
  EXPECT_GE(shared, 2) << "the corridor markers are seen by both robots";
  std::stringstream ss;
  write_multirobot_log(ss, log);
  const MultiRobotLog back = parse_multirobot_log(ss, "mem");
  EXPECT_EQ(back.robot(RobotId(1))->landmarks.size(), log.robot(RobotId(1))->landmarks.size());
  EXPECT_EQ(back.robot(RobotId(0))->scans.size(), log.robot(RobotId(0))->scans.size());
}

TEST(MrlogConvert, FeaturelessAndUnknownRobot) {
  WorldRecordOptions o;
  o.duration_s = 2.0;
  o.featureless = true;
  o.robots = {1};
  const MultiRobotLog log = record_world(sim::load_world_file(kWorld), o);
  ASSERT_EQ(log.robots.size(), 1u);
  for (float r : log.robot(RobotId(1))->scans.front().ranges_m) EXPECT_TRUE(std::isinf(r));
  o.robots = {7};
  EXPECT_THROW(record_world(sim::load_world_file(kWorld), o), InputError);
}

CarmenLog synthetic_carmen(int n) {
  CarmenLog log;
  for (int i = 0; i < n; ++i) {
    CarmenScan s;
    s.stamp_ns = sec_to_ns(100.0 + 0.1 * i);
    s.scan.ranges_m.assign(10, 2.0f);
    s.scan.stamp_ns = s.stamp_ns;
    s.T_world_laser = SE2(0.2 * i, 0.0, 0.0);
    s.T_odom_laser = SE2(5.0 + 0.2 * i, 1.0, 0.0);
    log.scans.push_back(s);
  }
  return log;
}

TEST(MrlogConvert, CarmenSplitRezeroesOdometryAndAddsVirtualMarkers) {
  CarmenConvertOptions o;
  o.split = 2;
  MultiRobotLog raw = convert_carmen({synthetic_carmen(40)}, {false}, o);
  ASSERT_EQ(raw.robots.size(), 2u);
  EXPECT_EQ(raw.robot(RobotId(1))->scans.size(), 20u);
  EXPECT_NEAR(raw.robot(RobotId(1))->odometry.front().T_odom_base.x(), 0.0, 1e-12);
  EXPECT_NEAR(raw.robot(RobotId(1))->odometry.back().T_odom_base.x(), 0.2 * 19, 1e-9);
  EXPECT_TRUE(raw.robot(RobotId(0))->truth.empty());
  EXPECT_THROW(convert_carmen({synthetic_carmen(40)}, {false},
                              [] {
                                CarmenConvertOptions c;
                                c.virtual_marker_spacing_m = 2;
                                return c;
                              }()),
               InputError);  // no reference in a raw log
  o.virtual_marker_spacing_m = 2.0;
  const MultiRobotLog corrected = convert_carmen({synthetic_carmen(40)}, {true}, o);
  EXPECT_GE(corrected.markers.size(), 3u);
  EXPECT_EQ(corrected.robot(RobotId(0))->truth.size(), 20u);
  EXPECT_FALSE(corrected.robot(RobotId(0))->landmarks.empty());
  EXPECT_FALSE(corrected.robot(RobotId(1))->landmarks.empty());
  EXPECT_THROW(convert_carmen({synthetic_carmen(4), synthetic_carmen(4)}, {false, false}, o), InputError);
}

}  // namespace
}  // namespace cairn::mrlog
