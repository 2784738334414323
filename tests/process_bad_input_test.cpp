// Bad input at the process level: each binary exits non-zero with one clear line naming what is
// wrong (file, key, argument), and leaves files already written alone.
#include <gtest/gtest.h>

#include <unistd.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

#include "base_station/store/journal.h"
#include "cairn_msgsPubSubTypes.h"
#include "common/navigation.h"
#include "dds/cdr.h"
#include "dds/domain_lease.h"
#include "run_command.h"

namespace cairn::test {
namespace {

namespace fs = std::filesystem;

std::string temp_file(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

TEST(ProcessBadInput, SimulatorRejectsMissingAndMalformedWorlds) {
  auto r = run_command(bin("cairn_sim") + " --world /nonexistent/world.yaml --out " + ::testing::TempDir());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("/nonexistent/world.yaml"), std::string::npos) << r.output;

  const std::string bad = temp_file("bad_world.yaml", "name: x\nmap: {image: [unclosed\n");
  r = run_command(bin("cairn_sim") + " --world " + bad + " --out " + ::testing::TempDir());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bad_world.yaml"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("line"), std::string::npos) << r.output;
}

TEST(ProcessBadInput, MissionNamesTheMisspelledKey) {
  std::string text;
  std::ifstream in(source_path("tests/worlds/two_robots.yaml"));
  ASSERT_TRUE(in) << "tests/worlds/two_robots.yaml missing";
  text.assign(std::istreambuf_iterator<char>(in), {});
  const auto pos = text.find("resolution_m");
  ASSERT_NE(pos, std::string::npos);
  text.replace(pos, 12, "resolutoin_m");
  const fs::path dir = fs::path(::testing::TempDir()) / "mission_bad_key";
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::copy_file(source_path("worlds/office.pgm"), dir / "office.pgm", fs::copy_options::overwrite_existing);
  std::string world_text = text;
  const auto img = world_text.find("../../worlds/office.pgm");
  if (img != std::string::npos) world_text.replace(img, 23, "office.pgm");
  const std::string world = (dir / "world.yaml").string();
  std::ofstream(world) << world_text;
  const auto r = run_command(bin("cairn_mission") + " --world " + world + " --out " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("key 'map.resolutoin_m' is not a known key"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out" / "logs")) << "nothing should be started for a bad world";
}

TEST(ProcessBadInput, BaseRejectsMalformedStartPose) {
  const auto r = run_command(bin("cairn_base") + " --out " + ::testing::TempDir() + "/base_bad --start 0,1,nan,0");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--start '0,1,nan,0'"), std::string::npos) << r.output;
}

TEST(ProcessBadInput, BaseRejectsMalformedEntryHints) {
  for (const char* hint : {"1,2,3", "1,2,3,30,0.5,nan", "1,2,3,30,0,10", "1,2,3,30,-0.5,10", "x,2,3,30,0.5,10"}) {
    const auto r =
        run_command(bin("cairn_base") + " --out " + ::testing::TempDir() + "/base_hint --start-hint " + hint);
    EXPECT_EQ(r.exit_code, 2) << hint << ": " << r.output;
    EXPECT_NE(r.output.find("--start-hint '" + std::string(hint) + "'"), std::string::npos) << r.output;
  }
}

TEST(ProcessBadInput, BaseRefusesAJournalThatIsNotOneAndLeavesItAlone) {
  const std::string dir = ::testing::TempDir() + "/base_bad_journal";
  std::filesystem::create_directories(dir);
  const std::string text = "victims found: 3\n";
  std::ofstream(dir + "/journal.sqlite") << text;
  const auto r = run_command(bin("cairn_base") + " --out " + dir + " --port 0");
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find(dir + "/journal.sqlite"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("not a database"), std::string::npos) << r.output;
  std::ifstream in(dir + "/journal.sqlite");
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()), text);
}

TEST(ProcessBadInput, BaseSkipsAndNamesDamagedJournalRecordsAndKeepsThem) {
  const std::string dir = ::testing::TempDir() + "/base_damaged_journal_" + std::to_string(getpid());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::string error;
  {
    auto journal = base::Journal::open(dir + "/journal.sqlite", {}, &error);
    ASSERT_TRUE(journal) << error;
    base::JournalRecord cut;
    cut.kind = base::JournalKind::kKeyframe;
    cut.robot = RobotId(1);
    cut.key = 3;
    cut.payload = {0, 1, 0, 0, 7, 7};  // a CDR header and two bytes of a keyframe
    ASSERT_TRUE(journal->append({cut}, &error)) << error;
  }
  const auto lease = dds::DomainLease::claim({}, &error);
  ASSERT_TRUE(lease) << error;
  const auto r = run_command("(timeout 20 " + bin("cairn_base") + " --domain " + std::to_string(lease->domain_id()) +
                             " --out " + dir + " --port 0 & sleep 2; kill -TERM $!; wait $!)");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("skipped keyframe 3 of robot1: not a whole sample"), std::string::npos) << r.output;
  std::ifstream in(dir + "/summary.json");
  const auto summary = nlohmann::json::parse(in);
  EXPECT_EQ(summary["journal"]["skipped_records"], 1) << summary.dump();
  EXPECT_EQ(summary["journal"]["records"], 1) << summary.dump();  // still there for a later look
}

/// One journal record of robot 5 (the robot of the tests below).
base::JournalRecord robot5_record(base::JournalKind kind, int64_t key, std::vector<uint8_t> payload) {
  base::JournalRecord r;
  r.kind = kind;
  r.robot = RobotId(5);
  r.key = key;
  r.payload = std::move(payload);
  return r;
}

/// A fresh folder `name` whose journal holds `records`: a base started on it resumes from them.
std::string folder_with_journal(const std::string& name, const std::vector<base::JournalRecord>& records) {
  const std::string dir = ::testing::TempDir() + "/" + name + "_" + std::to_string(getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string error;
  const auto journal = base::Journal::open(dir + "/journal.sqlite", {}, &error);
  EXPECT_TRUE(journal && journal->append(records, &error)) << error;
  return dir;
}

/// Runs cairn_base on `dir` until its one robot is finished: its output and its summary.json.
std::pair<CommandResult, nlohmann::json> run_base_on(const std::string& dir) {
  std::string error;
  const auto lease = dds::DomainLease::claim({}, &error);
  EXPECT_TRUE(lease) << error;
  if (!lease) return {};
  const auto r = run_command("timeout 30 " + bin("cairn_base") + " --domain " + std::to_string(lease->domain_id()) +
                             " --out " + dir + " --port 0 --robots 1");
  std::ifstream in(dir + "/summary.json");
  return {r, nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false)};
}

// Not bad input, but the same journal path: a robot the base knows only from its statuses (none of
// its data got through) is in the summary, flagged not linked, not left out.
TEST(ProcessBadInput, ARobotKnownOnlyFromItsStatusesIsInTheSummary) {
  cairn_msgs::RobotStatus status;
  status.robot_id(5);
  status.finished(true);
  const std::string dir = folder_with_journal(
      "base_status_only",
      {robot5_record(base::JournalKind::kStatus, 0, dds::to_cdr<cairn_msgs::RobotStatusPubSubType>(status))});
  const auto [r, summary] = run_base_on(dir);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  ASSERT_EQ(summary["robots"].size(), 1u) << summary.dump();
  EXPECT_EQ(summary["robots"][0]["id"], 5);
  EXPECT_EQ(summary["robots"][0]["linked"], false);
  EXPECT_EQ(summary["robots"][0]["keyframes"], 0);
  EXPECT_EQ(summary["unlinked_robots"], nlohmann::json::array({5}));
}

// The operator's commands and verdicts survive a base restart (a command with what the robot last
// said of it); a damaged command record is named and kept, not fatal.
TEST(ProcessBadInput,
     OperatorCommandsVerdictsAlertAcksKeepOutAreasObjectIdsAndAlignmentsSurviveABaseRestartAndADamagedOneIsNamed) {
  cairn_msgs::RobotStatus status;
  status.robot_id(5);
  status.finished(true);
  status.command_seq(7);
  status.command_state(uint8_t(CommandState::kDone));
  status.command_note("stopped; holding until resumed");
  const std::string stop =
      R"({"seq": 7, "robot": 5, "kind": 1, "local_m": [0, 0], "global_m": [0, 0], "sent_ns": 4000000000})";
  const std::string verdict = R"({"robot": 5, "seq": 3, "verdict": "confirmed", "note": "alive", "at_ns": 1})";
  const std::string keep_out =
      R"({"seq": 1, "action": 2, "area": 1, "min_m": [2, 3], "max_m": [4, 5], "stopped": [], "at_ns": 9})";
  const std::string ack = R"({"key": "object:5-3"})";
  const std::string object_id = R"({"report": [5, 3], "shown": [5, 3], "order": 0})";
  const std::string bad_object_id = R"({"report": [5], "shown": [5, 3], "order": 1})";
  const std::string alignment = R"({"robot": 5, "x_m": 1.5, "y_m": -2, "yaw_deg": 30})";
  const std::string bad_alignment = R"({"robot": 5, "x_m": "east", "y_m": -2, "yaw_deg": 30})";
  const std::string dir = folder_with_journal(
      "base_commands",
      {robot5_record(base::JournalKind::kStatus, 0, dds::to_cdr<cairn_msgs::RobotStatusPubSubType>(status)),
       robot5_record(base::JournalKind::kCommand, 7, {stop.begin(), stop.end()}),
       robot5_record(base::JournalKind::kCommand, 8, {'{', '"', 's'}),
       robot5_record(base::JournalKind::kVerdict, 3, {verdict.begin(), verdict.end()}),
       robot5_record(base::JournalKind::kSearch, 1, {keep_out.begin(), keep_out.end()}),
       robot5_record(base::JournalKind::kSession, 99, {'{', '"', 'r'}),
       robot5_record(base::JournalKind::kAlertAck, 1, {ack.begin(), ack.end()}),
       robot5_record(base::JournalKind::kAlertAck, 2, {'{', '}'}),
       robot5_record(base::JournalKind::kObjectId, 1, {object_id.begin(), object_id.end()}),
       robot5_record(base::JournalKind::kObjectId, 2, {bad_object_id.begin(), bad_object_id.end()}),
       robot5_record(base::JournalKind::kAlignment, 0, {alignment.begin(), alignment.end()}),
       robot5_record(base::JournalKind::kAlignment, 1, {bad_alignment.begin(), bad_alignment.end()})});
  const auto [r, summary] = run_base_on(dir);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("skipped operator command 8 of robot5"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("skipped robot session 99 of robot5: robot session record: not a JSON object"),
            std::string::npos)
      << r.output;
  ASSERT_EQ(summary["commands"].size(), 1u) << summary.dump();
  EXPECT_EQ(summary["commands"][0]["seq"], 7);
  EXPECT_EQ(summary["commands"][0]["kind"], "stop");
  EXPECT_EQ(summary["commands"][0]["state"], "done");
  EXPECT_NE(r.output.find("skipped alert acknowledgement 2 of robot5: alert acknowledgement: no \"key\" string"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("skipped object id 2 of robot5: object id record: 'report' is not [robot, seq] of two "
                          "non-negative integers"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("skipped operator alignment 1 of robot5: \"x_m\" must be a number"), std::string::npos)
      << r.output;
  EXPECT_EQ(summary["journal"]["skipped_records"], 5);
  // The damaged records are kept for a later look; robot 5's session (the status's) is journaled.
  EXPECT_EQ(summary["journal"]["records"], 13);
  // The operator's alignment is judged again (robot 5 sent no keyframes: refused, saying so).
  ASSERT_EQ(summary["alignments"].size(), 1u) << summary.dump();
  EXPECT_EQ(summary["alignments"][0]["x_m"], 1.5);
  EXPECT_EQ(summary["alignments"][0]["state"], "refused");
  EXPECT_FALSE(summary["alignments"][0]["reason"].get<std::string>().empty());
  EXPECT_EQ(summary["alerts_acknowledged"], nlohmann::json::array({"object:5-3"}));
  ASSERT_EQ(summary["verdicts"].size(), 1u) << summary.dump();
  EXPECT_EQ(summary["verdicts"][0]["object"], "5-3");
  EXPECT_EQ(summary["verdicts"][0]["verdict"], "confirmed");
  EXPECT_EQ(summary["verdicts"][0]["note"], "alive");
  // The operator's keep-out area is back too.
  ASSERT_EQ(summary["search"]["keep_out"].size(), 1u) << summary.dump();
  EXPECT_EQ(summary["search"]["keep_out"][0]["max_m"], nlohmann::json::array({4.0, 5.0}));
}

TEST(ProcessBadInput, EveryProcessNamesTheSecurityFileItCannotRead) {
  const std::string dir = ::testing::TempDir() + "/no_such_identity";
  const std::string world = std::string(CAIRN_SOURCE_DIR) + "/worlds/office.yaml";
  for (const std::string& cmd :
       {bin("cairn_agent") + " --robot 0", bin("cairn_base") + " --port 0 --out " + dir + "_out",
        bin("cairn_sim") + " --world " + world + " --out " + dir + "_gt"}) {
    const auto r = run_command(cmd + " --security " + dir);
    EXPECT_NE(r.exit_code, 0) << cmd << "\n" << r.output;
    EXPECT_NE(r.output.find("DDS security: cannot read " + dir + "/ca.pem"), std::string::npos) << cmd << "\n"
                                                                                                << r.output;
  }
}

TEST(ProcessBadInput, AgentRejectsBadConfigAndRobotId) {
  const std::string cfg = temp_file("agent_bad.yaml", "keyframer: {max_interval_s: zero}\n");
  auto r = run_command(bin("cairn_agent") + " --robot 0 --config " + cfg);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("keyframer.max_interval_s"), std::string::npos) << r.output;
  r = run_command(bin("cairn_agent") + " --robot -4");
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("--robot"), std::string::npos) << r.output;
  r = run_command(bin("cairn_agent") + " --robot 0 --teammate-intensity nan");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--teammate-intensity: not finite"), std::string::npos) << r.output;
}

TEST(ProcessBadInput, SlamBlamesALogWithoutScansNotTheOutputFolder) {
  // Odometry only (a robot whose laser died): the log is what is wrong, exit 2.
  const std::string log =
      temp_file("odometry_only.log", "ODOM 0 0 0 0 0 0 1.0 host 1.0\nODOM 0.1 0 0 0 0 0 1.1 host 1.1\n");
  const auto r = run_command(bin("cairn_slam") + " --log " + log + " --out " + ::testing::TempDir() + "/slam_no_scans");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("odometry_only.log: no laser scans"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("cannot write"), std::string::npos) << r.output;
}

TEST(ProcessBadInput, GraphOptimiserExitsTwoOnAMalformedGraph) {
  const std::string g2o = temp_file("bad.g2o", "VERTEX_SE2 0 0 0 0\nEDGE_SE2 0 1 1 0 nan 1 0 0 1 0 1\n");
  const auto r = run_command(bin("cairn_g2o_opt") + " " + g2o);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bad.g2o"), std::string::npos) << r.output;
}

TEST(ProcessBadInput, EvalKeepsExistingFilesOnMalformedInput) {
  const fs::path dir = fs::path(::testing::TempDir()) / "eval_bad_input";
  fs::create_directories(dir);
  std::ofstream(dir / "gt_objects.csv") << "id,class,x_m,y_m,z_m\n0,victim,1,2,3\n";
  std::ofstream(dir / "objects.csv") << "id,class,x_m,y_m,z_m\n0,victim,1,2\n";
  const auto before = fs::file_size(dir / "objects.csv");
  const auto r = run_command(bin("cairn_eval") + " --ground-truth " + dir.string() + " --results " + dir.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("objects.csv:2"), std::string::npos) << r.output;
  EXPECT_EQ(fs::file_size(dir / "objects.csv"), before);
}

}  // namespace
}  // namespace cairn::test
