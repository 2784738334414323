// Real laser data through the ROS 2 path: the MIT CSAIL raw log converted to a ROS 2 bag
// (cairn_bag_from_carmen: sensor_msgs/LaserScan + nav_msgs/Odometry in MCAP) and played by
// cairn_replay into cairn_agent --ros2 must give the keyframes cairn_agent --log gives on the same
// log: the same keyframes at the same stamps, at the same place in the robot's own frame.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "base_station/store/journal.h"
#include "cairn_msgsPubSubTypes.h"
#include "dds/cdr.h"
#include "dds/domain_lease.h"
#include "run_command.h"

namespace cairn::test {
namespace {

namespace fs = std::filesystem;

const std::string kMitLog = std::string(CAIRN_SHARED_DATA_DIR) + "/carmen/mit-csail/mit-csail.clf";

/// The keyframes a base journaled, in sequence order.
std::vector<cairn_msgs::Keyframe> journaled_keyframes(const fs::path& journal_path) {
  std::string error;
  auto journal = base::Journal::open(journal_path.string(), {}, &error);
  EXPECT_TRUE(journal) << error;
  std::vector<cairn_msgs::Keyframe> out;
  if (!journal) return out;
  const auto contents = journal->load(&error);
  EXPECT_TRUE(contents) << error;
  for (const auto& r : contents ? contents->records : std::vector<base::JournalRecord>{}) {
    if (r.kind != base::JournalKind::kKeyframe) continue;
    cairn_msgs::Keyframe kf;
    EXPECT_TRUE((dds::from_cdr<cairn_msgs::KeyframePubSubType>(r.payload, &kf)));
    out.push_back(kf);
  }
  return out;
}

TEST(Ros2Bag, TheCsailLogAsARos2BagGivesTheKeyframesOfTheLogItself) {
  if (!fs::exists(kMitLog)) GTEST_SKIP() << "SKIPPED: data absent: " << kMitLog;
  const fs::path dir = fs::path(::testing::TempDir()) / ("ros2_bag_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path bag = dir / "csail.mcap";
  const CommandResult convert =
      run_command(bin("cairn_bag_from_carmen") + " " + kMitLog + " " + bag.string() + " --namespace robot0");
  ASSERT_EQ(convert.exit_code, 0) << convert.output;

  std::string error;
  const auto lease = dds::DomainLease::claim({}, &error);
  ASSERT_TRUE(lease) << error;
  const std::string domain = std::to_string(lease->domain_id());
  auto base = [&](const std::string& out) {
    return "timeout 300 " + bin("cairn_base") + " --domain " + domain + " --out " + (dir / out).string() +
           " --robots 1 --start 0,0,0,0 --port 0 > " + (dir / (out + ".log")).string() + " 2>&1";
  };
  // The log read by the agent itself.
  const CommandResult a = run_command("(" + base("log") + " & timeout 300 " + bin("cairn_agent") +
                                      " --robot 0 --domain " + domain + " --log " + kMitLog + "; s=$?; wait; exit $s)");
  ASSERT_EQ(a.exit_code, 0) << a.output;
  // The bag on ROS 2 topics (rt/robot0/scan, rt/robot0/odom), at twenty times real time, with
  // cairn_record --ros2 taking the ROS 2 topics down as they go by.
  const fs::path rerecorded = dir / "rerecorded.mcap";
  // At 20x over DDS the scan and odom topics may arrive a second of log time (50 ms of wall time)
  // apart: with the default 1 s the agent would take the laser for lost (dead reckoning) now and then.
  const fs::path config = dir / "agent.yaml";
  std::ofstream(config) << "odometry: {laser_timeout_s: 20}\n";
  const CommandResult b = run_command(
      "(" + base("ros2") + " & timeout 300 " + bin("cairn_agent") + " --robot 0 --domain " + domain + " --config " +
      config.string() + " --ros2 --ros2-namespace robot0 --ros2-reliable --ros2-idle-end 3 --no-navigation > " +
      (dir / "agent.log").string() + " 2>&1 & timeout 300 " + bin("cairn_record") + " --domain " + domain +
      " --robots 1 --ros2 --ros2-reliable --topics /robot0/ --out " + rerecorded.string() + " > " +
      (dir / "record.log").string() + " 2>&1 & rec=$!; timeout 300 " + bin("cairn_replay") + " " + bag.string() +
      " --domain " + domain + " --speed 20 --wait 10 --subscribers 2; s=$?; kill -INT $rec; wait; exit $s)");
  ASSERT_EQ(b.exit_code, 0) << b.output << run_command("cat " + (dir / "agent.log").string()).output;

  const auto from_log = journaled_keyframes(dir / "log" / "journal.sqlite");
  const auto from_bag = journaled_keyframes(dir / "ros2" / "journal.sqlite");
  ASSERT_GT(from_log.size(), 500u);
  ASSERT_EQ(from_bag.size(), from_log.size());
  double worst_m = 0, worst_rad = 0;
  for (size_t i = 0; i < from_log.size(); ++i) {
    ASSERT_EQ(from_bag[i].seq(), from_log[i].seq());
    ASSERT_EQ(from_bag[i].stamp_ns(), from_log[i].stamp_ns()) << "keyframe " << i;
    const auto &p = from_log[i].T_local_base(), &q = from_bag[i].T_local_base();
    worst_m = std::max(worst_m, std::hypot(p.x_m() - q.x_m(), p.y_m() - q.y_m()));
    worst_rad = std::max(worst_rad, std::abs(std::remainder(p.yaw_rad() - q.yaw_rad(), 2 * M_PI)));
  }
  // The odometry's yaw went through a quaternion (~1e-16 rad): scan matching may carry that far
  // further (1e-13 m seen), never to a different keyframe or a visible offset.
  EXPECT_LT(worst_m, 1e-6);
  EXPECT_LT(worst_rad, 1e-6);
  std::cout << "keyframes " << from_log.size() << ", worst difference " << worst_m << " m, " << worst_rad << " rad\n";

  // The bag as ROS 2 tools read it: Foxglove's MCAP reader, and its ROS 2 CDR decoder with the
  // standard message definitions (and with the bag's own schema text: both must agree).
  const fs::path checker = fs::path(source_path("tests/bag/mcap_check.mjs"));
  if (run_command("command -v node").exit_code != 0 || !fs::exists(checker.parent_path() / "node_modules/@mcap/core")) {
    GTEST_SKIP()
        << "SKIPPED (reference decoders only): node or tests/bag/node_modules missing (scripts/install_deps.sh)";
  }
  const CommandResult check =
      run_command("node " + checker.string() + " check " + bag.string() + " --topic /robot0/scan --topic /robot0/odom");
  EXPECT_EQ(check.exit_code, 0) << check.output;
  const CommandResult decode = run_command("node " + checker.string() + " decode-ros2 " + bag.string());
  EXPECT_EQ(decode.exit_code, 0) << decode.output;
  EXPECT_NE(decode.output.find("\"sensor_msgs/msg/LaserScan\":1988"), std::string::npos) << decode.output;
  // And what cairn_record took off the wire: every scan and odometry message, decodable as sent.
  const CommandResult again = run_command("node " + checker.string() + " decode-ros2 " + rerecorded.string());
  EXPECT_EQ(again.exit_code, 0) << again.output << run_command("cat " + (dir / "record.log").string()).output;
  EXPECT_NE(again.output.find("\"sensor_msgs/msg/LaserScan\":1988"), std::string::npos) << again.output;
  EXPECT_NE(again.output.find("\"nav_msgs/msg/Odometry\":1988"), std::string::npos) << again.output;
}

}  // namespace
}  // namespace cairn::test
