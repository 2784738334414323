// The control centre's commands end to end, over real processes: a mission runs (cairn_mission:
// simulator, agent, base), and the test acts as the console's operator over HTTP: a command
// without the token is refused, "go to" drives the simulated robot to the point (checked against
// the simulator's ground truth) and is reported done, "home" brings it back and ends the mission;
// pausing the exploration holds the robot, and no goal is planned into a keep-out area.
// Eigen (through trajectory.h) before httplib.h: <resolv.h>'s _res macro breaks Eigen's headers.
#include "common/trajectory.h"

#include <gtest/gtest.h>
#include <httplib.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <future>
#include <thread>

#include <nlohmann/json.hpp>

#include "run_command.h"
#include "tools/mission/ports.h"

namespace cairn::test {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const char* kToken = "feedc0de0123456789abcdef01234567";

class Operator {
 public:
  explicit Operator(int port) : client_("127.0.0.1", port) { client_.set_connection_timeout(2); }

  nlohmann::json get(const std::string& path) {
    const auto res = client_.Get(path);
    if (!res || res->status != 200) return nlohmann::json();
    return nlohmann::json::parse(res->body, nullptr, false);
  }
  /// HTTP status of a command (-1: no answer).
  int post(const nlohmann::json& body, const std::string& token = kToken, const std::string& path = "/api/commands") {
    httplib::Headers headers;
    if (!token.empty()) headers.emplace("Authorization", "Bearer " + token);
    const auto res = client_.Post(path, headers, body.dump(), "application/json");
    last_body_ = res ? res->body : "no answer";
    return res ? res->status : -1;
  }
  const std::string& last_body() const { return last_body_; }

  /// The entry of list `path` whose `key` is `value` (null when there is none yet).
  nlohmann::json entry(const std::string& path, const char* key, int value) {
    const nlohmann::json list = get(path);
    if (list.is_array())
      for (const auto& e : list)
        if (e[key] == value) return e;
    return nlohmann::json();
  }
  nlohmann::json robot(int id) { return entry("/api/robots", "id", id); }
  /// One field of robot `id`'s entry: null while there is none (or the base did not answer).
  nlohmann::json robot_field(int id, const char* key) {
    const nlohmann::json r = robot(id);
    return r.is_object() && r.contains(key) ? r[key] : nlohmann::json();
  }
  nlohmann::json command(int seq) { return entry("/api/commands", "seq", seq); }

 private:
  httplib::Client client_;
  std::string last_body_;
};

/// The one-robot operator mission (tests/worlds/operator_one_robot.yaml) in the background, its
/// console on `port` with the test's operator token.
std::future<CommandResult> start_one_robot_mission(const fs::path& out, int port) {
  fs::remove_all(out);
  return std::async(std::launch::async, [out, port] {
    return run_command(bin("cairn_mission") + " --world " + source_path("tests/worlds/operator_one_robot.yaml") +
                       " --out " + out.string() + " --port " + std::to_string(port) + " --operator-token " + kToken +
                       " --timeout 300");
  });
}

/// Polls `done` every 200 ms for up to `timeout_s`; true once it holds.
template <typename Done>
bool wait_for(double timeout_s, Done&& done) {
  const auto until = Clock::now() + std::chrono::duration<double>(timeout_s);
  while (Clock::now() < until) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  return false;
}

TEST(OperatorCommands, GoToDrivesTheSimulatedRobotThereAndHomeEndsTheMission) {
  const fs::path out = fs::path(::testing::TempDir()) / ("operator_" + std::to_string(getpid()));
  const int port = mission::free_port();
  ASSERT_GT(port, 0);
  auto mission = start_one_robot_mission(out, port);
  Operator op(port);
  const Eigen::Vector2d target(6.0, 7.5);  // down the corridor from where it entered (1.2, 7.5)
  const nlohmann::json go = {{"robot", 0}, {"kind", "goto"}, {"x_m", target.x()}, {"y_m", target.y()}};
  ASSERT_TRUE(wait_for(120, [&] { return op.robot(0).is_object() && !op.robot(0)["pose_m"].is_null(); }))
      << "robot 0 never appeared placed on the console";

  // Without the operator token: refused, nothing sent.
  EXPECT_EQ(op.post(go, ""), 401);
  EXPECT_EQ(op.post(go, "not-the-token"), 401);
  EXPECT_TRUE(op.get("/api/commands").empty());

  // Go to the point (the map must reach it first: 400 "outside the map" until then).
  int seq = 0;
  ASSERT_TRUE(wait_for(60, [&] {
    if (op.post(go) != 202) return false;
    seq = nlohmann::json::parse(op.last_body())["seqs"][0];
    return true;
  })) << op.last_body();
  nlohmann::json command;
  ASSERT_TRUE(wait_for(120, [&] {
    command = op.command(seq);
    return command.is_object() && (command["state"] == "done" || command["state"] == "failed");
  })) << command.dump();
  EXPECT_EQ(command["state"], "done") << command.dump();
  // The console's robot list (rebuilt every second) shows it there too, holding.
  nlohmann::json pose;
  EXPECT_TRUE(wait_for(5, [&] {
    pose = op.robot(0)["pose_m"];
    return pose.size() == 3u && (Eigen::Vector2d(pose[0], pose[1]) - target).norm() < 0.8;
  })) << pose.dump();

  // Home: back where it entered, and the mission ends.
  ASSERT_EQ(op.post({{"robot", "all"}, {"kind", "home"}}), 202) << op.last_body();
  const CommandResult result = mission.get();
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("#token="), std::string::npos) << "the operator's link is printed";

  // The simulator's truth: the robot was at the point, and ended near where it entered.
  const Trajectory truth = read_trajectory_csv((out / "ground_truth" / "gt_robot0.csv").string());
  ASSERT_FALSE(truth.empty());
  double closest_m = 1e9;
  for (const auto& s : truth) closest_m = std::min(closest_m, (s.pose.translation() - target).norm());
  EXPECT_LT(closest_m, 0.6);
  EXPECT_LT((truth.back().pose.translation() - Eigen::Vector2d(1.2, 7.5)).norm(), 1.5);
  // Every command and its end are in the mission's summary.
  std::ifstream in(out / "map" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  ASSERT_EQ(summary["commands"].size(), 2u) << summary["commands"].dump();
  EXPECT_EQ(summary["commands"][1]["kind"], "goto");  // newest first
  EXPECT_EQ(summary["commands"][1]["state"], "done");
  EXPECT_EQ(summary["commands"][0]["kind"], "home");
  EXPECT_EQ(summary["commands"][0]["state"], "done") << summary["commands"].dump();
}

TEST(OperatorCommands, PauseHoldsTheExploringRobotAndNoGoalIsSentIntoAKeepOutArea) {
  const fs::path out = fs::path(::testing::TempDir()) / ("search_" + std::to_string(getpid()));
  const int port = mission::free_port();
  ASSERT_GT(port, 0);
  auto mission = start_one_robot_mission(out, port);
  Operator op(port);
  auto goals = [&] {
    const nlohmann::json status = op.get("/api/status");
    return status.contains("exploration") ? status["exploration"]["goals"] : nlohmann::json::array();
  };
  nlohmann::json g;
  ASSERT_TRUE(wait_for(120, [&] {
    const nlohmann::json now = goals();
    if (!now.empty()) g = now[0];
    return !now.empty();
  })) << "the base never planned a goal for robot 0";

  // Pause: the base stops the exploring robot (a journaled stop command), and it stays put.
  ASSERT_EQ(op.post({{"action", "pause"}}, kToken, "/api/search"), 202) << op.last_body();
  nlohmann::json stop;
  ASSERT_TRUE(wait_for(30, [&] {
    stop = op.command(1);
    return stop.is_object() && stop["kind"] == "stop" && stop["state"] == "done";
  })) << stop.dump();
  EXPECT_EQ(op.get("/api/search")["paused"], true);
  EXPECT_EQ(op.post({{"robot", 0}, {"kind", "resume"}}), 400) << "a robot is not resumed while the search is paused";
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // the robot list is rebuilt every second
  const nlohmann::json held = op.robot(0)["pose_m"];
  std::this_thread::sleep_for(std::chrono::seconds(3));
  const nlohmann::json later = op.robot(0)["pose_m"];
  ASSERT_EQ(held.size(), 3u);
  ASSERT_EQ(later.size(), 3u);
  EXPECT_LT(std::hypot(later[0].get<double>() - held[0].get<double>(), later[1].get<double>() - held[1].get<double>()),
            0.15);

  // A keep-out area over the goal it was driving to, then resume: no goal is planned inside it.
  const double gx = g["x_m"], gy = g["y_m"];
  ASSERT_EQ(
      op.post({{"action", "keep_out"}, {"area_m", {gx - 1.0, gy - 1.0, gx + 1.0, gy + 1.0}}}, kToken, "/api/search"),
      202)
      << op.last_body();
  // The robot is told the area in its own frame, and its own planner holds it (its status says so).
  nlohmann::json robot;
  ASSERT_TRUE(wait_for(30, [&] {
    robot = op.robot_field(0, "link");
    return robot.is_object() && robot.value("keep_out_held", 0u) >= 1u &&
           robot["keep_out_held"] == robot["keep_out_sent"];
  })) << robot.dump();
  // The link's round trip, measured by the base from the probes its acks carry and the robot echoes.
  ASSERT_TRUE(robot.contains("rtt_ms")) << robot.dump();
  EXPECT_GE(robot["rtt_ms"].get<int>(), 0);
  EXPECT_LT(robot["rtt_ms"].get<int>(), 2000) << "a loopback link";
  auto in_area = [&](const nlohmann::json& pose) {
    return std::abs(pose[0].get<double>() - gx) < 1.0 && std::abs(pose[1].get<double>() - gy) < 1.0;
  };
  const bool started_outside = !in_area(later);
  ASSERT_EQ(op.post({{"action", "resume"}}, kToken, "/api/search"), 202) << op.last_body();
  ASSERT_TRUE(wait_for(30, [&] {
    const nlohmann::json resume = op.command(2);
    return resume.is_object() && resume["kind"] == "resume";
  })) << "resuming the exploration resumes the robot the pause stopped";
  // Either goals outside the area, or (the area closing the way on) nothing reachable is left and
  // the base sends the team home, which ends the mission.
  int plans_seen = 0;
  auto ended = [&] { return mission.wait_for(std::chrono::seconds(0)) == std::future_status::ready; };
  wait_for(8, [&] {
    const nlohmann::json pose = op.robot_field(0, "pose_m");
    if (started_outside && pose.size() == 3u) EXPECT_FALSE(in_area(pose)) << "robot 0 drove into the area";
    for (const auto& goal : goals()) {
      ++plans_seen;
      EXPECT_FALSE(std::abs(goal["x_m"].get<double>() - gx) <= 1.0 && std::abs(goal["y_m"].get<double>() - gy) <= 1.0)
          << goal.dump();
    }
    return ended();
  });
  EXPECT_TRUE(plans_seen > 0 || ended()) << "no goal was planned after the resume, and the mission goes on";
  if (!ended()) {
    // The base may end the mission (everything explored, the team home) between the check and the
    // post; then the post gets no answer, which is not a failure.
    const int status = op.post({{"robot", "all"}, {"kind", "home"}});
    if (status != 202) {
      EXPECT_EQ(mission.wait_for(std::chrono::seconds(30)), std::future_status::ready)
          << "\"all home\" refused (" << status << ": " << op.last_body() << ") while the mission goes on";
    }
  }
  const CommandResult result = mission.get();
  ASSERT_EQ(result.exit_code, 0) << result.output;
}

}  // namespace
}  // namespace cairn::test
