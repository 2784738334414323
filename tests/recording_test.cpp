// A mission recorded as MCAP (cairn_mission --ros2 --record) and played back (cairn_replay) into a fresh
// base station on another domain: the base, fed only the recording, must merge the same robots and
// place the same objects as it did live. The recording is then read by the reference MCAP reader
// (tests/bag/mcap_check.mjs), which skips loudly without Node.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "bag/mcap_reader.h"
#include "common/yaml_config.h"
#include "dds/domain_lease.h"
#include "run_command.h"
#include "tools/eval/mission_eval.h"

namespace cairn::test {
namespace {

namespace fs = std::filesystem;

TEST(Recording, AMissionRecordedAsMcapReplaysIntoAFreshBaseWithTheSameRobotsAndObjects) {
  const std::string world = "tests/worlds/two_robots_meet.yaml";
  const fs::path out = fs::path(::testing::TempDir()) / ("recording_" + std::to_string(getpid()));
  fs::remove_all(out);
  fs::create_directories(out);
  const fs::path bag = out / "mission.mcap";
  const CommandResult live =
      run_command(bin("cairn_mission") + " --world " + source_path(world) + " --out " + (out / "live").string() +
                  " --port 0 --timeout 400 --ros2 --record " + bag.string());
  ASSERT_EQ(live.exit_code, 0) << live.output;

  // Every Cairn topic is in the recording, sensor topics per robot.
  std::ifstream in(bag, std::ios::binary);
  std::string error;
  const auto summary = bag::read_mcap_summary(in, &error);
  ASSERT_TRUE(summary) << error;
  std::map<std::string, uint64_t> counts;
  for (const auto& [id, n] : summary->channel_message_counts) counts[summary->channels.at(id).topic] = n;
  for (const char* topic :
       {"cairn/keyframe", "cairn/status", "cairn/object", "cairn/mission_clock", "cairn/correction",
        "cairn/robot0/laser_scan", "cairn/robot1/odometry", "cairn/robot1/rgbd", "cairn/robot0/cmd_vel"}) {
    EXPECT_GT(counts[topic], 0u) << topic;
  }
  EXPECT_GT(counts["cairn/keyframe"], 40u);

  // Replayed into a fresh base (what the robots sent it, nothing of what it answered).
  const auto start = YamlConfig::load(source_path(world)).node()["robots"][0]["start"].as<std::vector<double>>();
  const auto lease = dds::DomainLease::claim({}, &error);
  ASSERT_TRUE(lease) << error;
  const std::string domain = std::to_string(lease->domain_id());
  const fs::path replayed = out / "replayed";
  const std::string base = "timeout 300 " + bin("cairn_base") + " --domain " + domain + " --out " + replayed.string() +
                           " --robots 2 --port 0 --start 0," + std::to_string(start[0]) + "," +
                           std::to_string(start[1]) + "," + std::to_string(start[2]);
  const std::string replay = "timeout 300 " + bin("cairn_replay") + " " + bag.string() + " --domain " + domain +
                             " --topics cairn/keyframe cairn/object cairn/status cairn/mission_clock";
  const CommandResult r = run_command(base + " > " + (out / "base.log").string() + " 2>&1 & " + replay + " > " +
                                      (out / "replay.log").string() +
                                      " 2>&1; replay=$?; wait $!; echo \"base exit $?, replay exit $replay\"");
  EXPECT_NE(r.output.find("base exit 0, replay exit 0"), std::string::npos)
      << r.output << "\n"
      << run_command("cat " + (out / "replay.log").string()).output;

  // What the robots sent arrives unchanged: their own-frame objects are byte for byte the live ones.
  // The merge itself is not: the base links robots by closures it searches among what has arrived
  // at each of its polls, so the cross-robot closures (and the merged poses, ~1 cm) can differ.
  const auto slurp = [](const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
  };
  const std::string own_frame = slurp(out / "live" / "map" / "objects_robot_frame.csv");
  EXPECT_FALSE(own_frame.empty());
  EXPECT_EQ(slurp(replayed / "objects_robot_frame.csv"), own_frame);

  const std::string truth = (out / "live" / "ground_truth").string();
  const eval::MissionScore a = eval::evaluate_mission(truth, (out / "live" / "map").string());
  const eval::MissionScore b = eval::evaluate_mission(truth, replayed.string());
  ASSERT_EQ(b.robots.size(), a.robots.size()) << eval::format_score(b);
  for (size_t i = 0; i < a.robots.size(); ++i) {
    ASSERT_TRUE(a.robots[i].global && b.robots[i].global) << eval::format_score(b);
    EXPECT_EQ(b.robots[i].keyframes, a.robots[i].keyframes);
    EXPECT_NEAR(b.robots[i].global->ate_rmse_m, a.robots[i].global->ate_rmse_m, 0.05) << eval::format_score(b);
  }
  EXPECT_EQ(b.objects.matched, a.objects.matched) << eval::format_score(b);
  EXPECT_EQ(b.objects.detected, a.objects.detected) << eval::format_score(b);
  EXPECT_NEAR(b.objects.mean_error_xy_m, a.objects.mean_error_xy_m, 0.05) << eval::format_score(b);

  // A recording cut in half (a pulled battery) replays up to the cut, and says where it was cut.
  const fs::path half = out / "half.mcap";
  fs::copy_file(bag, half);
  fs::resize_file(half, fs::file_size(bag) / 2);
  const CommandResult cut = run_command("timeout 120 " + bin("cairn_replay") + " " + half.string() + " --domain " +
                                        domain + " --speed 0 --wait 0");
  EXPECT_EQ(cut.exit_code, 5) << cut.output;
  EXPECT_NE(cut.output.find("no footer and closing magic"), std::string::npos) << cut.output;
  EXPECT_NE(cut.output.find("truncated or corrupt; reading stops here"), std::string::npos) << cut.output;
  EXPECT_NE(cut.output.find("not closed cleanly"), std::string::npos) << cut.output;

  // The reference reader (Foxglove's @mcap/core) reads the same file: indexes, CRCs, counts.
  const fs::path checker = fs::path(source_path("tests/bag/mcap_check.mjs"));
  if (run_command("command -v node").exit_code != 0 || !fs::exists(checker.parent_path() / "node_modules/@mcap/core")) {
    GTEST_SKIP() << "SKIPPED (reference reader only): node or tests/bag/node_modules missing (scripts/install_deps.sh)";
  }
  const CommandResult check = run_command("node " + checker.string() + " check " + bag.string() +
                                          " --topic cairn/keyframe --topic cairn/robot0/laser_scan");
  EXPECT_EQ(check.exit_code, 0) << check.output;
  // The base's ROS 2 topics, decoded by Foxglove's ROS 2 CDR reader with the standard Jazzy
  // definitions: the map's grid, one box, label and ellipsoid per object after a DELETEALL, the frames.
  const CommandResult ros2 = run_command("node " + checker.string() + " decode-ros2 " + bag.string());
  ASSERT_EQ(ros2.exit_code, 0) << ros2.output;
  EXPECT_NE(ros2.output.find("\"resolution\":0.05"), std::string::npos) << ros2.output;
  EXPECT_NE(ros2.output.find("\"markers\":" + std::to_string(1 + 3 * a.objects.detected)), std::string::npos)
      << ros2.output;
  EXPECT_NE(ros2.output.find("\"map->robot1/odom\""), std::string::npos) << ros2.output;
  EXPECT_NE(ros2.output.find("\"robot1/odom->robot1/base_link\""), std::string::npos) << ros2.output;
}

}  // namespace
}  // namespace cairn::test
