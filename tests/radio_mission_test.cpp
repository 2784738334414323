// End to end behind the emulated radio (cairn_mission --link-* / --radio-model; needs root, nft
// and tc): the base station in its own network namespace, the robots on the other side of a lossy,
// slow link, or cut one by one where the simulated radio says they are out of range.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "run_command.h"
#include "tools/eval/mission_eval.h"

namespace cairn::test {
namespace {

namespace fs = std::filesystem;

bool can_emulate_radio() { return geteuid() == 0 && fs::exists("/usr/sbin/nft") && fs::exists("/usr/sbin/tc"); }

/// Everything each agent sent was stored: its keyframes without gaps, and its objects.
void expect_everything_delivered(const fs::path& out) {
  std::ifstream in(out / "map" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  ASSERT_EQ(summary["robots"].size(), 2u);
  for (const auto& robot : summary["robots"]) {
    EXPECT_EQ(robot["keyframes"], robot["link"]["keyframes_sent"]) << robot.dump();
    EXPECT_EQ(robot["missing_keyframes"], 0) << robot.dump();
    EXPECT_EQ(robot["object_reports"], robot["link"]["objects_sent"]) << robot.dump();
    EXPECT_TRUE(robot["link"]["finished"].get<bool>()) << robot.dump();
  }
}

TEST(RadioMission, LossySlowRadioLinkLosesNothing) {
  // The base station behind an emulated radio (10 % loss each way, 250 kbit/s, an ordinary Wi-Fi
  // link through rubble): reliable DDS with the agents' outboxes, their link budget and the base's
  // acks must still deliver every keyframe and object, without drowning the link in overhead.
  if (!can_emulate_radio()) {
    GTEST_SKIP() << "needs root, nft and tc for the emulated radio link (network namespaces)";
  }
  // Twice real time: at the simulator's own speed (25x on this scripted world) odometry ran more than
  // a second of mission time ahead of the first laser scan on a loaded machine, and the agent took
  // its laser for lost (the decision goes by stamps alone).
  const MissionRun run = run_mission("tests/worlds/two_robots_meet.yaml", "lossy",
                                     "--timeout 400 --speed 2 --link-loss 10 --link-kbit 250");
  const fs::path& out = run.out;
  const CommandResult& r = run.result;
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("10 % loss, 250 kbit/s each way"), std::string::npos) << r.output;
  std::ifstream results_in(out / "results.json");
  const nlohmann::json results = nlohmann::json::parse(results_in, nullptr, false);
  ASSERT_TRUE(results.contains("radio")) << r.output;
  // The radio did lose packets both ways, and what crossed it stayed within 3x the payload (2.0x
  // measured; 4.1x before the link budget, mostly discovery probes and fragment repair requests).
  EXPECT_GT(results["radio"]["to_base"]["lost_packets"].get<int>(), 0) << results["radio"].dump();
  EXPECT_GT(results["radio"]["to_robots"]["lost_packets"].get<int>(), 0) << results["radio"].dump();
  EXPECT_LT(results["radio"]["overhead"].get<double>(), 3.0) << results["radio"].dump();
  expect_everything_delivered(out);
  const eval::MissionScore score = eval::evaluate_mission((out / "ground_truth").string(), (out / "map").string());
  ASSERT_EQ(score.robots.size(), 2u);
  ASSERT_TRUE(score.robots[0].global);
  EXPECT_LT(score.robots[0].global->ate_rmse_m, 0.20);
  EXPECT_GE(score.objects.recall(), 0.75) << eval::format_score(score);
}

TEST(RadioMission, ARobotOutOfRangeBehindWallsIsCutAndDeliversEverythingOnceBack) {
  // The team's only antenna at robot 0's entry: robot 1's route takes it into the east rooms, four
  // walls and 16 m away, where the multi-wall model puts it below the receiver's sensitivity. Its
  // agent's packets are dropped both ways while it is there; what it made meanwhile waits in its
  // outbox and reaches the base once it is back in the corridor.
  if (!can_emulate_radio()) {
    GTEST_SKIP() << "needs root, nft and tc for the emulated radio link (network namespaces)";
  }
  // Twice real time: robot 1 is out of range for about ten seconds of wall time.
  const MissionRun run =
      run_mission("tests/worlds/two_robots_radio.yaml", "radio_model", "--timeout 400 --speed 2 --radio-model");
  const fs::path& out = run.out;
  const CommandResult& r = run.result;
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("radio: robot 1 out of range"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("radio: robot 1 back in range"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("NOT APPLIED"), std::string::npos) << r.output;
  std::ifstream results_in(out / "results.json");
  const nlohmann::json results = nlohmann::json::parse(results_in, nullptr, false);
  ASSERT_TRUE(results.contains("radio_model")) << r.output;
  const nlohmann::json& links = results["radio_model"];
  ASSERT_EQ(links.size(), 2u) << links.dump();
  // Robot 0 stays near the antenna (at most a moment on the edge of range in the room at x = 7.5 m).
  EXPECT_LT(links[0]["out_of_range_s"].get<double>(), 3.0) << links.dump();
  EXPECT_GE(links[1]["cuts"].get<int>(), 1) << links.dump();
  EXPECT_GT(links[1]["out_of_range_s"].get<double>(), 5.0) << links.dump();
  EXPECT_GT(links[1]["dropped_packets"].get<int>(), 0) << "the cut did not drop robot 1's packets: " << links.dump();
  expect_everything_delivered(out);
  EXPECT_GT(fs::file_size(out / "radio.png"), 10000u) << "the radio's picture";
  const eval::MissionScore score = eval::evaluate_mission((out / "ground_truth").string(), (out / "map").string());
  EXPECT_GE(score.objects.recall(), 0.75) << eval::format_score(score);
}

}  // namespace
}  // namespace cairn::test
