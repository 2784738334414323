#include "common/carmen_log.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "common/errors.h"

namespace cairn {
namespace {

std::string write_log(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

std::string flaser(int n, const std::string& range, const std::string& tail) {
  std::string s = "FLASER " + std::to_string(n);
  for (int i = 0; i < n; ++i) s += " " + range;
  return s + " " + tail + "\n";
}

TEST(CarmenLog, ParsesFlaserOdomAndSkipsTheRest) {
  const auto path =
      write_log("ok.clf", "# comment\nPARAM robot_x 1\n" + flaser(180, "1.5", "1 2 0.5 3 4 0.25 100.5 host 100.6") +
                              "ODOM 3 4 0.25 0.1 0.2 0 100.55 host 100.56\nNEFF 12\nWEIRDTHING 1 2 3\n" +
                              flaser(361, "81.91", "0 0 0 0 0 0 101.0 host 101.1"));
  const CarmenLog log = read_carmen_log(path);
  ASSERT_EQ(log.scans.size(), 2u);
  ASSERT_EQ(log.odometry.size(), 1u);
  EXPECT_EQ(log.stats.ignored_records, 3);
  EXPECT_EQ(log.stats.unknown_records, 1);
  const CarmenScan& s = log.scans[0];
  EXPECT_EQ(s.stamp_ns, sec_to_ns(100.5));
  EXPECT_EQ(s.scan.ranges_m.size(), 180u);
  EXPECT_NEAR(s.scan.angle_min_rad, -M_PI / 2, 1e-6);
  EXPECT_NEAR(s.scan.angle_increment_rad, M_PI / 180, 1e-7);
  EXPECT_NEAR(s.T_world_laser.x(), 1.0, 1e-12);
  EXPECT_NEAR(s.T_odom_laser.yaw(), 0.25, 1e-12);
  EXPECT_NEAR(log.scans[1].scan.angle_increment_rad, M_PI / 360, 1e-7);
  EXPECT_TRUE(std::isinf(log.scans[1].scan.ranges_m[0]));  // 81.91 = no return
  EXPECT_EQ(log.scans[0].line, 3);
}

TEST(CarmenLog, MalformedAndTruncatedLinesNameTheLine) {
  auto expect_error = [](const std::string& text, const std::string& needle) {
    const auto path = write_log("bad.clf", text);
    try {
      read_carmen_log(path);
      FAIL() << "no error for: " << needle;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_error("PARAM a b\n" + flaser(180, "1.0", "1 2 x 3 4 0.25 100.5 host 100.6"),
               "bad.clf:2: FLASER field x y theta is not a number: 'x'");
  expect_error("FLASER 180 1.0 2.0\n", "bad.clf:1: FLASER record ends before range (truncated?)");
  expect_error("FLASER -3\n", "num_readings must be a whole number");
  expect_error("ODOM 1 2 nan 0 0 0 1 h 1\n", "bad.clf:1: ODOM x y theta is not finite");
  // Found by the sanitized fuzz run: a huge timestamp overflowed the nanosecond stamp (UB).
  expect_error("ODOM 0 0 0 0 0 0 0666666666666666666666666666666666666666666666666666666666666666 h 1\n",
               "bad.clf:1: ODOM ipc_timestamp must be a time within +-9e9 s");
  expect_error("ODOM 0 0 0 0 0 0 nan h 1\n", "ODOM ipc_timestamp must be a time");
  EXPECT_THROW(read_carmen_log("/nonexistent/log.clf"), InputError);
}

TEST(CarmenLog, ReadsTheRealLogsWhenPresent) {
  const std::string dir = std::string(CAIRN_SHARED_DATA_DIR) + "/carmen/";
  const std::string mit = dir + "mit-csail/mit-csail.clf";
  const std::string aces = dir + "aces/aces-corrected.log.gz";
  if (!std::ifstream(mit) || !std::ifstream(aces)) GTEST_SKIP() << "data absent: " << mit << " or " << aces;
  const CarmenLog raw = read_carmen_log(mit);
  EXPECT_EQ(raw.scans.size(), 1988u);
  EXPECT_EQ(raw.scans[0].scan.ranges_m.size(), 361u);
  EXPECT_FALSE(is_corrected_log_name(mit));
  const CarmenLog gz = read_carmen_log(aces);
  EXPECT_EQ(gz.scans.size(), 440u);
  EXPECT_EQ(gz.scans[0].scan.ranges_m.size(), 180u);
  EXPECT_TRUE(is_corrected_log_name(aces));
  EXPECT_TRUE(is_corrected_log_name(dir + "intel/intel.gfs.log"));
}

}  // namespace
}  // namespace cairn
