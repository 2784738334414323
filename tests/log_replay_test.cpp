// The agent replays a recorded CARMEN log (instead of the simulator's topics) to a real base
// station over DDS; a truncated log is refused with its line number; a base station killed after
// acknowledging a robot's data rebuilds the map from its journal once restarted, with the robot
// long gone; an agent killed and restarted is a new session the base keeps apart, and with its
// outbox it resends what the killed run never delivered; with DDS Security, a team member's
// samples claiming another robot's id are refused.
#include <gtest/gtest.h>

#include <unistd.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "common/se2.h"
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

/// An empty folder `name` under the test's temporary directory (per process).
fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / (name + "_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// A whole text file ("" when it cannot be read).
std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
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
  const std::string base = bin("cairn_base") + " --domain " + std::to_string(domain) + " --out " +
                           (dir / "map").string() + " --robots 1 --start 0,0,0,0 --port 0";
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
  const nlohmann::json summary = nlohmann::json::parse(read_text(dir / "map" / "summary.json"));
  ASSERT_EQ(summary["robots"].size(), 1u);
  EXPECT_GE(summary["robots"][0]["link"]["keyframe_pose_updates"].get<int>(), 1) << summary.dump();
}

TEST(LogReplay, AnAgentWithNoBaseKeepsItsDataWaitingAndAStopSaysWhatTheBaseLacks) {
  // No base station on the domain (the radio is cut): the agent must not give up on its own after
  // its input ended; stopped with SIGTERM it exits 3 and says what was never acknowledged.
  if (!std::ifstream(kMitLog)) GTEST_SKIP() << "data absent: " << kMitLog;
  const fs::path dir = fresh_dir("agent_no_base");
  const std::string log = excerpt(dir, 200);
  std::string error;
  const auto lease = dds::DomainLease::claim({}, &error);
  ASSERT_TRUE(lease) << error;
  const std::string agent = bin("cairn_agent") + " --robot 0 --domain " + std::to_string(lease->domain_id()) +
                            " --log " + log + " --log-speed 0";
  // 12 s: the log's 200 scans take a moment; then it waits, and says so at once and every 10 s.
  const auto r = run_command("timeout --preserve-status -s TERM 12 " + agent);
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("waiting for the base station: acknowledged by the base: keyframes 0 of"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("stopped before the base station had everything: acknowledged by the base: keyframes 0 of"),
            std::string::npos)
      << r.output;
}

/// The number N in the agent's closing line "done: N keyframes, ...", or -1.
int agent_keyframes(const std::string& agent_log) {
  const auto at = agent_log.find("done: ");
  return at == std::string::npos ? -1 : std::atoi(agent_log.c_str() + at + 6);
}

TEST(LogReplay, KilledBaseResumesFromItsJournalAfterTheRobotIsGone) {
  if (!std::ifstream(kMitLog)) GTEST_SKIP() << "data absent: " << kMitLog;
  const fs::path dir = fs::path(::testing::TempDir()) / ("base_restart_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string log = excerpt(dir, 400);
  std::string error;
  const auto lease = dds::DomainLease::claim({}, &error);
  ASSERT_TRUE(lease) << error;
  const std::string domain = std::to_string(lease->domain_id());
  const std::string out = (dir / "map").string();
  // Base A waits for 2 robots, so it never exports on its own; robot 0 runs to the end (the agent
  // exits only once the base acknowledged all it sent), says "finished", and is gone. Then base A
  // is killed without a chance to write anything more.
  const std::string base_a = bin("cairn_base") + " --domain " + domain + " --out " + out + " --robots 2 --port 0";
  const std::string agent = bin("cairn_agent") + " --robot 0 --domain " + domain + " --log " + log;
  const std::string base_a_log = (dir / "base_a.log").string();
  const auto r = run_command("(" + base_a + " > " + base_a_log + " 2>&1 & pid=$!; " + agent + " > " +
                             (dir / "agent.log").string() + " 2>&1; status=$?; for i in $(seq 300); do grep -q " +
                             "'robot0 reports finished' " + base_a_log + " && break; sleep 0.1; done; kill -9 $pid; " +
                             "wait; exit $status)");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string agent_log = read_text(dir / "agent.log");
  const int sent = agent_keyframes(agent_log);
  ASSERT_GE(sent, 60) << agent_log;
  ASSERT_FALSE(fs::exists(dir / "map" / "summary.json")) << "base A exported before it was killed";

  // Base B: same results folder, no robot on the network. It must rebuild everything from the
  // journal, see robot 0 finished, and export.
  const auto b = run_command("timeout 120 " + bin("cairn_base") + " --domain " + domain + " --out " + out +
                             " --robots 1 --port 0");
  ASSERT_EQ(b.exit_code, 0) << b.output;
  EXPECT_NE(b.output.find("resumed from journal"), std::string::npos) << b.output;
  const nlohmann::json summary = nlohmann::json::parse(read_text(dir / "map" / "summary.json"));
  ASSERT_EQ(summary["robots"].size(), 1u) << summary.dump();
  EXPECT_EQ(summary["robots"][0]["keyframes"].get<int>(), sent) << summary.dump();
  EXPECT_EQ(summary["robots"][0]["missing_keyframes"].get<int>(), 0) << summary.dump();
  EXPECT_GT(summary["journal"]["restored_records"].get<int>(), sent) << summary.dump();
  EXPECT_EQ(summary["journal"]["skipped_records"].get<int>(), 0) << summary.dump();
  EXPECT_EQ(read_trajectory_csv((dir / "map" / "trajectory_robot0.csv").string()).size(), size_t(sent));

  // --new-mission keeps the old journal (renamed) and starts empty.
  const auto c = run_command("(timeout 20 " + bin("cairn_base") + " --domain " + domain + " --out " + out +
                             " --robots 1 --port 0 --new-mission & sleep 3; kill -TERM $!; wait $!)");
  EXPECT_EQ(c.exit_code, 0) << c.output;
  EXPECT_NE(c.output.find("previous mission's journal moved to"), std::string::npos) << c.output;
  std::ifstream fresh(dir / "map" / "summary.json");
  EXPECT_EQ(nlohmann::json::parse(fresh)["robots"].size(), 0u);
  int kept = 0;
  for (const auto& e : fs::directory_iterator(dir / "map"))
    kept += e.path().filename().string().rfind("journal.sqlite.", 0) == 0;
  EXPECT_GE(kept, 1);
}

TEST(LogReplay, AnAgentKilledAndRestartedIsANewSessionAndNothingIsDroppedOrOverwritten) {
  if (!std::ifstream(kMitLog)) GTEST_SKIP() << "data absent: " << kMitLog;
  const fs::path dir = fresh_dir("agent_restart");
  const std::string log = excerpt(dir, 400);
  std::string error;
  const auto lease = dds::DomainLease::claim({}, &error);
  ASSERT_TRUE(lease) << error;
  const std::string domain = std::to_string(lease->domain_id());
  const std::string out = (dir / "map").string();
  // Robot 0 replays the log at 4x real time (about 21 s) and is killed after 8 s; restarted with the
  // same arguments (as fast as it goes), it starts over from keyframe 0 in a new local frame.
  const std::string base =
      bin("cairn_base") + " --domain " + domain + " --out " + out + " --robots 1 --start 0,0,0,0 --port 0";
  const std::string agent = bin("cairn_agent") + " --robot 0 --domain " + domain + " --log " + log;
  const auto r =
      run_command("(" + base + " > " + (dir / "base.log").string() + " 2>&1 & base=$!; " + agent + " --log-speed 4 > " +
                  (dir / "agent_a.log").string() + " 2>&1 & a=$!; sleep 8; kill -9 $a; " + "wait $a; " + agent + " > " +
                  (dir / "agent_b.log").string() + " 2>&1; status=$?; wait $base; exit $status)");
  const std::string base_log = read_text(dir / "base.log");
  ASSERT_EQ(r.exit_code, 0) << r.output << base_log;
  const std::string agent_b = read_text(dir / "agent_b.log");
  const int sent = agent_keyframes(agent_b);
  ASSERT_GE(sent, 60) << agent_b;
  EXPECT_NE(base_log.find("started session"), std::string::npos) << base_log;

  const nlohmann::json summary = nlohmann::json::parse(read_text(dir / "map" / "summary.json"));
  ASSERT_EQ(summary["robots"].size(), 2u) << summary.dump();
  const nlohmann::json& first = summary["robots"][0];
  const nlohmann::json& second = summary["robots"][1];
  // What the first session delivered before it was killed is kept as it was.
  EXPECT_EQ(first["label"], "robot0") << summary.dump();
  EXPECT_GE(first["keyframes"].get<int>(), 5) << summary.dump();
  // The second session: every keyframe stored under a robot of its own (none taken as a duplicate
  // of the first's), linked to the first by closures (no start was given for it).
  EXPECT_EQ(second["label"], "robot0 session 2") << summary.dump();
  EXPECT_EQ(second["robot"].get<int>(), 0);
  EXPECT_EQ(second["keyframes"].get<int>(), sent) << summary.dump();
  EXPECT_EQ(second["missing_keyframes"].get<int>(), 0) << summary.dump();
  EXPECT_TRUE(second["linked"].get<bool>()) << summary.dump();
  ASSERT_EQ(summary["restarts"].size(), 1u) << summary.dump();
  EXPECT_EQ(summary["refused_overwrites"].get<int>(), 0) << summary.dump();
  EXPECT_EQ(summary["rejected_samples"].get<int>(), 0) << summary.dump();
}

TEST(LogReplay, AnAgentRebootedOutOfRadioRangeResendsWhatItHadFromItsOutbox) {
  if (!std::ifstream(kMitLog)) GTEST_SKIP() << "data absent: " << kMitLog;
  const fs::path dir = fresh_dir("agent_outbox");
  const std::string log = excerpt(dir, 400);
  std::string error;
  const auto lease = dds::DomainLease::claim({}, &error);
  ASSERT_TRUE(lease) << error;
  const std::string domain = std::to_string(lease->domain_id());
  // Run A has no base to talk to (out of radio range) and is killed after 8 s of the log at 4x: all
  // it made is unacknowledged. Run B, with the same outbox and a base in reach, must deliver A's
  // keyframes as A's session (before its own) and then its own.
  const std::string agent = bin("cairn_agent") + " --robot 0 --domain " + domain + " --log " + log + " --outbox " +
                            (dir / "outbox.sqlite").string();
  const std::string base = bin("cairn_base") + " --domain " + domain + " --out " + (dir / "map").string() +
                           " --robots 1 --start 0,0,0,0 --port 0";
  const auto r = run_command("(" + agent + " --log-speed 4 > " + (dir / "agent_a.log").string() +
                             " 2>&1 & a=$!; sleep 8; kill -9 $a; wait $a; " + base + " > " +
                             (dir / "base.log").string() + " 2>&1 & base=$!; " + agent + " > " +
                             (dir / "agent_b.log").string() + " 2>&1; status=$?; wait $base; exit $status)");
  const std::string agent_b = read_text(dir / "agent_b.log");
  ASSERT_EQ(r.exit_code, 0) << r.output << agent_b << read_text(dir / "base.log");
  const auto at = agent_b.find("left undelivered");
  ASSERT_NE(at, std::string::npos) << agent_b;
  const auto upto = agent_b.find("up to keyframe ", at);
  ASSERT_NE(upto, std::string::npos) << agent_b;
  const int a_keyframes = std::atoi(agent_b.c_str() + upto + 15) + 1;
  EXPECT_GE(a_keyframes, 10) << agent_b;
  EXPECT_NE(agent_b.find("the base has all it left"), std::string::npos) << agent_b;

  const nlohmann::json summary = nlohmann::json::parse(read_text(dir / "map" / "summary.json"));
  ASSERT_EQ(summary["robots"].size(), 2u) << summary.dump();  // without the outbox: B's alone
  const nlohmann::json& first = summary["robots"][0];
  const nlohmann::json& second = summary["robots"][1];
  EXPECT_EQ(first["label"], "robot0") << summary.dump();  // A: the session that ran first
  EXPECT_EQ(first["keyframes"].get<int>(), a_keyframes) << summary.dump();
  EXPECT_EQ(first["missing_keyframes"].get<int>(), 0) << summary.dump();
  EXPECT_EQ(second["label"], "robot0 session 2") << summary.dump();
  EXPECT_EQ(second["keyframes"].get<int>(), agent_keyframes(agent_b)) << summary.dump();
  EXPECT_EQ(second["missing_keyframes"].get<int>(), 0) << summary.dump();
  EXPECT_EQ(summary["refused_overwrites"].get<int>(), 0) << summary.dump();
}

TEST(LogReplay, ATeamMemberSpeakingForAnotherRobotIsRefusedAndCounted) {
  if (!std::ifstream(kMitLog)) GTEST_SKIP() << "data absent: " << kMitLog;
  const fs::path dir = fresh_dir("spoofed_robot");
  const std::string certs = (dir / "security").string();
  if (std::system(("bash " + std::string(CAIRN_SOURCE_DIR) + "/deploy/security/make_certs.sh " + certs +
                   " base robot1 > /dev/null")
                      .c_str()) != 0) {
    GTEST_SKIP() << "could not make certificates (is openssl installed?)";
  }
  const std::string log = excerpt(dir, 200);
  std::string error;
  const auto lease = dds::DomainLease::claim({}, &error);
  ASSERT_TRUE(lease) << error;
  const std::string domain = std::to_string(lease->domain_id());
  // Robot 1 replays the log with its own certificate; a second agent holding the same valid team
  // certificate (robot1's) claims to be robot 2 and replays it too, starting 4 s earlier so that its
  // samples reach the base before robot 1 finishes the mission.
  const std::string base = bin("cairn_base") + " --domain " + domain + " --out " + (dir / "map").string() +
                           " --robots 1 --start 1,0,0,0 --port 0 --security " + certs + "/base";
  const std::string agent =
      bin("cairn_agent") + " --domain " + domain + " --log " + log + " --security " + certs + "/robot1 --robot ";
  const auto r = run_command("(" + base + " > " + (dir / "base.log").string() + " 2>&1 & base=$!; " + agent + "2 > " +
                             (dir / "spoofer.log").string() + " 2>&1 & spoofer=$!; sleep 4; " + agent + "1 > " +
                             (dir / "agent.log").string() + " 2>&1; status=$?; wait $base; kill $spoofer; " +
                             "wait $spoofer; exit $status)");
  const std::string base_log = read_text(dir / "base.log");
  ASSERT_EQ(r.exit_code, 0) << r.output << base_log;
  const std::string agent_log = read_text(dir / "agent.log");
  const int sent = agent_keyframes(agent_log);
  ASSERT_GE(sent, 20) << agent_log;
  EXPECT_NE(base_log.find("does not hold robot2's certificate"), std::string::npos) << base_log;
  const nlohmann::json summary = nlohmann::json::parse(read_text(dir / "map" / "summary.json"));
  // Only robot 1 is known: nothing robot "2" sent (keyframes, objects, statuses) was taken.
  ASSERT_EQ(summary["robots"].size(), 1u) << summary.dump();
  EXPECT_EQ(summary["robots"][0]["id"].get<int>(), 1);
  EXPECT_EQ(summary["robots"][0]["keyframes"].get<int>(), sent);
  EXPECT_GE(summary["spoofed_samples"].get<int>(), sent) << summary.dump();
}

/// Two robots without laser (odometry and identified markers only, as the UTIAS MRCLAM robots):
/// each drives a loop among five markers; robot 1 starts elsewhere, facing another way.
std::string laserless_log(const fs::path& dir, std::vector<SE2>* truth_end) {
  const std::vector<Eigen::Vector2d> markers = {{0, 0}, {6, 0}, {6, 5}, {0, 5}, {3, 2.5}};
  const std::vector<SE2> starts = {SE2(1, 1, 0), SE2(5, 4, M_PI)};
  std::mt19937 rng(5);
  std::normal_distribution<double> n01;
  std::ostringstream log;
  log << "CAIRN_MRLOG 1\n";
  for (int robot = 0; robot < 2; ++robot) {
    SE2 truth = starts[size_t(robot)], odom;
    for (int i = 0; i <= 400; ++i) {  // 40 s at 10 Hz: straight 4 m, a half turn, back, a half turn
      const double t = 0.1 * i;
      log << "ODOM " << robot << " " << t << " " << odom.x() << " " << odom.y() << " " << odom.yaw() << "\n";
      for (int m = 0; i % 5 == 0 && m < 5; ++m) {
        const Eigen::Vector2d q = truth.inverse() * markers[size_t(m)];
        if (q.norm() > 6.0) continue;
        log << "LANDMARK " << robot << " " << t << " " << m << " " << q.norm() + 0.02 * n01(rng) << " "
            << std::atan2(q.y(), q.x()) + 0.01 * n01(rng) << " 0.05 0.02\n";
      }
      const int phase = (i / 100) % 2;  // 10 s straight, 10 s turning on a 0.6 m radius
      const SE2 step = phase == 0 ? SE2(0.04, 0, 0) : SE2(0.019, 0, M_PI / 100);
      truth = truth * step;
      odom = odom * SE2(step.x() * (1 + 0.01 * n01(rng)), 0.002 * n01(rng), step.yaw() + 0.002 * n01(rng));
    }
    truth_end->push_back(truth);
  }
  const fs::path path = dir / "laserless.mrlog";
  std::ofstream(path) << log.str();
  return path.string();
}

TEST(LogReplay, RobotsWithoutLaserArePlacedByOdometryAndMarkers) {
  // Neither robot has a laser: each agent makes keyframes from odometry alone, with the markers it
  // saw; the base places robot 1 (start unknown) on the markers both saw.
  const fs::path dir = fresh_dir("laserless");
  std::vector<SE2> truth_end;
  const std::string log = laserless_log(dir, &truth_end);
  std::string error;
  const auto lease = dds::DomainLease::claim({}, &error);
  ASSERT_TRUE(lease) << error;
  const std::string domain = std::to_string(lease->domain_id());
  const std::string base = bin("cairn_base") + " --domain " + domain + " --out " + (dir / "map").string() +
                           " --robots 2 --start 0,1,1,0 --port 0";
  const std::string agent = bin("cairn_agent") + " --domain " + domain + " --log " + log + " --log-speed 0 --robot ";
  const auto r =
      run_command("(" + base + " > " + (dir / "base.log").string() + " 2>&1 & pb=$!; " + agent + "0 & p0=$!; " + agent +
                  "1; s1=$?; wait $p0; s0=$?; wait $pb; sb=$?; exit $((s0 + s1 + sb)))");
  ASSERT_EQ(r.exit_code, 0) << r.output << read_text(dir / "base.log");
  EXPECT_NE(r.output.find("laser silent"), std::string::npos) << r.output;
  const nlohmann::json summary = nlohmann::json::parse(read_text(dir / "map" / "summary.json"));
  ASSERT_EQ(summary["robots"].size(), 2u) << summary.dump();
  for (int robot = 0; robot < 2; ++robot) {
    EXPECT_TRUE(summary["robots"][robot]["linked"].get<bool>()) << "robot " << robot << ": " << summary.dump();
    EXPECT_GE(summary["robots"][robot]["keyframes"].get<int>(), 20) << summary.dump();
    const Trajectory t =
        read_trajectory_csv((dir / "map" / ("trajectory_robot" + std::to_string(robot) + ".csv")).string());
    ASSERT_FALSE(t.empty()) << "robot " << robot;
    EXPECT_LT((t.back().pose.translation() - truth_end[size_t(robot)].translation()).norm(), 0.5)
        << "robot " << robot << " ends at " << t.back().pose.x() << ", " << t.back().pose.y();
  }
  EXPECT_EQ(summary["landmarks"].size(), 5u) << summary.dump();
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
