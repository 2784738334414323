// cairn_base: the base station. Merges every robot's keyframes and objects into one global map
// (base_station/core), serves the console, and exports the results when the mission ends.
#include <CLI/CLI.hpp>

#include <cmath>
#include <csignal>
#include <filesystem>
#include <sstream>

#include "base_station/app/base_node.h"
#include "common/logging.h"
#include "common/random_token.h"

namespace {
cairn::base::BaseNode* g_node = nullptr;
void on_signal(int) {
  if (g_node) g_node->stop();
}

/// "id,x_m,y_m,yaw_rad" -> a robot's start pose; false when malformed.
bool parse_start(const std::string& text, cairn::RobotId* robot, cairn::SE2* pose) {
  std::istringstream ss(text);
  int id;
  double x, y, yaw;
  char c1, c2, c3;
  if (!(ss >> id >> c1 >> x >> c2 >> y >> c3 >> yaw) || c1 != ',' || c2 != ',' || c3 != ',' || id < 0 ||
      !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(yaw)) {
    return false;
  }
  *robot = cairn::RobotId(id);
  *pose = cairn::SE2(x, y, yaw);
  return true;
}
/// "id,x_m,y_m,yaw_deg,sigma_xy_m,sigma_yaw_deg" -> an entry hint; false when malformed.
bool parse_entry_hint(const std::string& text, cairn::RobotId* robot, cairn::base::EntryHint* hint) {
  std::istringstream ss(text);
  int id;
  double v[5];
  char c[5];
  if (!(ss >> id >> c[0] >> v[0] >> c[1] >> v[1] >> c[2] >> v[2] >> c[3] >> v[3] >> c[4] >> v[4]) || id < 0)
    return false;
  for (int i = 0; i < 5; ++i) {
    if (c[i] != ',' || !std::isfinite(v[i])) return false;
  }
  if (!(v[3] > 0) || !(v[4] > 0)) return false;
  constexpr double kRad = M_PI / 180.0;
  *robot = cairn::RobotId(id);
  *hint = cairn::base::EntryHint{cairn::SE2(v[0], v[1], v[2] * kRad), v[3], v[4] * kRad};
  return true;
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Cairn base station"};
  cairn::base::BaseNodeOptions options;
  std::vector<std::string> starts;
  std::string log_level = "info";
  app.add_option("--domain", options.domain_id, "DDS domain id")->check(CLI::Range(0, 232));
  app.add_option("--peer", options.peers, "IPv4 address of a robot (DDS unicast discovery); repeatable");
  app.add_option("--out", options.out_dir, "results folder")->required();
  app.add_option("--security", options.security_dir,
                 "DDS Security: folder with ca.pem, cert.pem, key.pem (deploy/security/make_certs.sh)");
  app.add_option("--robots", options.expected_robots, "finish when this many robots are done (0 = run until Ctrl-C)");
  app.add_option("--start", starts, "known start pose of a robot: id,x_m,y_m,yaw_rad (repeatable)");
  std::vector<std::string> hints;
  app.add_option("--start-hint", hints,
                 "roughly where a robot entered: id,x_m,y_m,yaw_deg,sigma_xy_m,sigma_yaw_deg (repeatable); bounds its "
                 "link search, never links it alone");
  app.add_option("--port", options.console.port, "console HTTP port (0 = any free port)");
  app.add_option(
      "--console-bind,--bind", options.console.bind_address,
      "console address to listen on (default 127.0.0.1, this machine only; 0.0.0.0 opens it to the network)");
  bool no_shm = false;
  app.add_flag("--no-shm", no_shm, "UDP only, no shared memory (e.g. behind an emulated radio link)");
  app.add_flag("--slow-link", options.slow_link,
               "the robots are behind a slow radio (a few hundred kbit/s): DDS discovery announces every 10 s, not 3");
  app.add_flag("--serve", options.serve_after_finish, "keep the console up after the mission");
  app.add_option(
      "--journal", options.journal_path,
      "journal of everything received (SQLite; default <out>/journal.sqlite); a restarted base resumes from it");
  app.add_flag("--new-mission", options.new_mission, "move an existing journal aside and start an empty map");
  std::string operator_token;
  app.add_option("--operator-token", operator_token,
                 "secret the console's commands need (drive, stop, resume, home); default: a fresh random one, "
                 "printed in the console's address at start; 'off': the console only watches");
  std::string coordination = "coordinated";
  app.add_option("--exploration", coordination,
                 "how robots get frontiers: coordinated (no two on one area), nearest (each its own nearest) or "
                 "saliency (coordinated, frontiers near salient spots the cameras saw first)")
      ->check(CLI::IsMember({"coordinated", "nearest", "saliency"}));
  app.add_option("--meet-after", options.active_linking.after_s,
                 "active linking: a robot not on the map this many mission seconds after its first keyframe is "
                 "sent to meet a teammate where its entry hint or the operator's alignment puts it (0 = never)")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--ros2", options.ros2,
               "publish the mission as ROS 2 topics for RViz2/Foxglove: map, tf, robotN/path, cairn/objects "
               "(MarkerArray), cairn/object_clouds (PointCloud2); docs/ros2.md");
  app.add_option("--log-level", log_level);
  CLI11_PARSE(app, argc, argv);
  options.use_shared_memory = !no_shm;
  options.active_linking.enabled = options.active_linking.after_s > 0;
  if (operator_token.empty()) operator_token = cairn::random_hex_token();
  if (operator_token != "off") options.operator_token = operator_token;
  options.exploration.coordination = coordination == "nearest"
                                         ? cairn::base::ExplorationOptions::Coordination::kNearestFrontier
                                         : cairn::base::ExplorationOptions::Coordination::kCoordinated;
  if (coordination == "saliency") options.exploration.saliency_weight = 3.0;
  cairn::set_log_level(log_level);
  auto log = cairn::make_logger("base");

  for (const auto& s : starts) {
    cairn::RobotId robot;
    cairn::SE2 pose;
    if (!parse_start(s, &robot, &pose)) {
      log->error("--start '{}': expected id,x_m,y_m,yaw_rad with finite numbers", s);
      return 2;
    }
    options.robot_starts[robot] = pose;
  }
  for (const auto& h : hints) {
    cairn::RobotId robot;
    cairn::base::EntryHint hint;
    if (!parse_entry_hint(h, &robot, &hint)) {
      log->error(
          "--start-hint '{}': expected id,x_m,y_m,yaw_deg,sigma_xy_m,sigma_yaw_deg with finite numbers and "
          "positive sigmas",
          h);
      return 2;
    }
    options.entry_hints[robot] = hint;
  }
  std::error_code ec;
  std::filesystem::create_directories(options.out_dir, ec);
  if (ec) {
    log->error("cannot create results folder '{}': {}", options.out_dir, ec.message());
    return 2;
  }
  std::string error;
  auto node = cairn::base::BaseNode::create(options, cairn::base::MapperOptions{}, &error);
  if (!node) {
    log->error("{}", error);
    return 3;
  }
  g_node = node.get();
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  const int code = node->run();
  g_node = nullptr;
  return code;
}
