#include "tools/slam/slam_eval.h"
#include "tools/slam/slam_runner.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "common/errors.h"

namespace cairn::slam {
namespace {

CarmenScan scan(StampNs stamp, std::vector<float> ranges, const SE2& pose) {
  CarmenScan s;
  s.stamp_ns = stamp;
  s.scan.ranges_m = std::move(ranges);
  s.T_world_laser = pose;
  return s;
}

TEST(SlamEval, ReferenceMatchesCorrectedScansToRawByRanges) {
  CarmenLog raw, corrected;
  raw.scans = {scan(100, {1, 2, 3}, SE2()), scan(200, {1, 2, 4}, SE2()), scan(300, {1, 2, 5}, SE2()),
               scan(400, {1, 2, 4}, SE2())};
  corrected.scans = {scan(0, {9, 9, 9}, SE2()), scan(1, {1, 2, 4}, SE2(1, 0, 0)), scan(2, {1, 2, 4}, SE2(2, 0, 0))};
  int unmatched = -1;
  std::vector<size_t> scan_index;
  const Trajectory ref = reference_from_corrected(corrected, &raw, &unmatched, &scan_index);
  ASSERT_EQ(ref.size(), 2u);
  EXPECT_EQ(ref[0].stamp_ns, 200);  // duplicates are taken in order
  EXPECT_EQ(ref[1].stamp_ns, 400);
  EXPECT_EQ(ref[1].pose.x(), 2.0);
  EXPECT_EQ(unmatched, 1);
  EXPECT_EQ(scan_index, (std::vector<size_t>{1, 2}));  // the corrected scans the poses came from
}

TEST(SlamEval, RelationsErrorOfAPerfectAndAPerturbedTrajectory) {
  Trajectory est;
  for (int i = 0; i < 10; ++i) est.push_back({StampNs(i) * kNsPerSec, SE2(i * 0.5, 0.0, 0.1 * i)});
  const double offset_s = 1000.25;
  std::vector<Relation> rel;
  for (int i = 0; i + 2 < 10; ++i) {
    rel.push_back({i + offset_s, i + 2 + offset_s, est[size_t(i)].pose.between(est[size_t(i) + 2].pose)});
  }
  rel.push_back({55.0, 56.0, SE2()});  // not on the trajectory
  EXPECT_NEAR(estimate_time_offset_s(rel, est), offset_s, 1e-9);
  const RelationsError perfect = relations_error(rel, est, offset_s);
  EXPECT_EQ(perfect.used, 8);
  EXPECT_EQ(perfect.total, 9);
  EXPECT_NEAR(perfect.trans_mean_m, 0.0, 1e-9);
  rel[0].T_1_2 = rel[0].T_1_2 * SE2(0.1, 0.0, 0.0);
  const RelationsError one_off = relations_error(rel, est, offset_s);
  EXPECT_NEAR(one_off.trans_mean_m, 0.1 / 8, 1e-9);
}

TEST(SlamEval, MalformedRelationsNameTheLine) {
  const std::string path = ::testing::TempDir() + "/bad.relations";
  std::ofstream(path) << "1 2 0 0 0 0 0 0\n1 2 x 0 0 0 0 0\n";
  try {
    read_relations(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(":2:"), std::string::npos) << e.what();
  }
  std::remove(path.c_str());
}

TEST(SlamRunner, OdometryDropoutHoldsTheReadingBeforeIt) {
  CarmenLog log;
  for (int i = 0; i < 6; ++i) {
    CarmenScan s = scan(StampNs(i) * kNsPerSec, std::vector<float>(180, 3.f), SE2());
    s.scan.angle_min_rad = float(-M_PI / 2);
    s.scan.angle_increment_rad = float(M_PI / 180);
    s.T_odom_laser = SE2(0.1 * i, 0, 0);
    s.T_world_laser = s.T_odom_laser;
    log.scans.push_back(s);
  }
  SlamRunOptions options;
  options.odometry_dropout_first = 2;
  options.odometry_dropout_last = 4;
  const SlamRunResult r = run_slam(log, false, options);
  ASSERT_EQ(r.odometry.size(), 6u);
  for (int i : {2, 3, 4}) EXPECT_EQ(r.odometry[size_t(i)].pose.x(), 0.1) << i;  // scan 1's reading
  EXPECT_EQ(r.odometry[5].pose.x(), 0.5);
  EXPECT_EQ(r.stats.scans, 6);
}

}  // namespace
}  // namespace cairn::slam
