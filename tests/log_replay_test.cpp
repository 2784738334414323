// The agent replays a recorded CARMEN log (instead of the simulator's topics) to a real base
// station over DDS; a truncated log is refused with its line number.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "common/trajectory.h"
#include "dds/domain_lease.h"
#include "run_command.h"

namespace cairn::test {
namespace {

namespace fs = std::filesystem;

const std::string kMitLog = std::string(CAIRN_SHARED_DATA_DIR) + "/carmen/mit-csail/mit-csail.clf";

/// The first `scans` FLASER lines of the raw MIT CSAIL log.
std::string excerpt(const fs::path& dir, int scans) {
  std::ifstream in(kMitLog);
  const fs::path out = dir / "excerpt.clf";
  std::ofstream o(out);
  std::string line;
  int n = 0;
  while (n < scans && std::getline(in, line)) {
    if (line.rfind("FLASER", 0) == 0) ++n;
    o << line << "\n";
  }
  return out.string();
}

TEST(LogReplay, AgentReplaysACarmenLogToTheBaseOverDds) {
  if (!std::ifstream(kMitLog)) GTEST_SKIP() << "data absent: " << kMitLog;
  const fs::path dir = fs::path(::testing::TempDir()) / ("log_replay_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string log = excerpt(dir, 400);
  std::string error;
  const auto lease = dds::DomainLease::claim({}, &error);  // no concurrent mission shares it
  ASSERT_TRUE(lease) << error;
  const int domain = lease->domain_id();
  const std::string base = bin("cairn_base") + " --domain " + std::to_string(domain) + " --out " + (dir / "map").string() +
                           " --robots 1 --start 0,0,0,0 --port 0";
  const std::string agent = bin("cairn_agent") + " --robot 0 --domain " + std::to_string(domain) + " --log " + log;
  const auto r = run_command("(" + base + " > " + (dir / "base.log").string() + " 2>&1 & " + agent +
                             "; status=$?; wait; exit $status)");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Trajectory t = read_trajectory_csv((dir / "map" / "trajectory_robot0.csv").string());
  EXPECT_GE(t.size(), 60u);  // ~400 scans over tens of metres
  double path_m = 0;
  for (size_t i = 1; i < t.size(); ++i) path_m += (t[i].pose.translation() - t[i - 1].pose.translation()).norm();
  EXPECT_GT(path_m, 20.0);
  EXPECT_TRUE(fs::exists(dir / "map" / "map.pgm"));
  // The agent's loop-closed keyframe poses reached the base (cairn/keyframe_poses).
  std::ifstream in(dir / "map" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  ASSERT_EQ(summary["robots"].size(), 1u);
  EXPECT_GE(summary["robots"][0]["link"]["keyframe_pose_updates"].get<int>(), 1) << summary.dump();
}

TEST(LogReplay, TruncatedLogIsRefusedWithItsLineNumber) {
  const fs::path dir = fs::path(::testing::TempDir()) / "log_truncated";
  fs::create_directories(dir);
  const fs::path log = dir / "truncated.clf";
  std::ofstream(log) << "PARAM x 1\nFLASER 180 1.0 1.0 1.0\n";
  const auto r = run_command(bin("cairn_agent") + " --robot 0 --log " + log.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("truncated.clf:2"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace cairn::test
