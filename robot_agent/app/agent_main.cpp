// cairn_agent: one per robot. Reads its robot's sensor topics, runs local 2D SLAM and the object
// pipeline (robot_agent/core), and publishes keyframes, objects and status to the base station.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <iostream>
#include <optional>

#include "common/carmen_log.h"
#include "common/errors.h"
#include "common/huge_pages.h"
#include "common/logging.h"
#include "common/multirobot_log.h"
#include "robot_agent/app/agent_config.h"
#include "robot_agent/app/agent_node.h"

namespace {
std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }

/// On a budgeted radio the agent sends its loop-closed keyframe poses at most this often (mission s).
constexpr double kSlowLinkKeyframePosesInterval_s = 20.0;
}  // namespace

int main(int argc, char** argv) {
  cairn::reexec_with_huge_pages(argv);  // common/huge_pages.h: ~-12 % SLAM CPU
  CLI::App app{"Cairn robot agent"};
  int robot = -1;
  std::string config_path, log_path, log_level = "info";
  cairn::agent::AgentNodeOptions node;
  cairn::agent::SensorInput input;
  app.add_option("--robot", robot, "robot id")->required()->check(CLI::Range(0, 1000));
  app.add_option("--domain", node.domain_id, "DDS domain id")->check(CLI::Range(0, 232));
  app.add_option("--peer", node.peers, "IPv4 address of a DDS peer (base station, other robots); repeatable");
  app.add_option("--security", node.security_dir,
                 "DDS Security: folder with ca.pem, cert.pem, key.pem (deploy/security/make_certs.sh)");
  app.add_option("--config", config_path, "agent YAML (keyframer, odometry, objects)");
  app.add_option("--log", log_path,
                 "replay a log instead of the sensor topics: CARMEN (.clf/.log, plain or .gz), or a Cairn "
                 "multi-robot log (docs/multirobot_log_format.md; this robot's records are used)");
  app.add_option("--log-speed", input.log_options.speed, "log replay speed, times real time (0 = as fast as possible)");
  double link_budget_kbit = 0;
  app.add_option("--link-budget-kbit", link_budget_kbit,
                 "this robot's share of a slow radio, kbit/s: everything it sends is paced below it, a victim or "
                 "hazard first, then keyframes, then keyframe poses (0 = no limit)")
      ->check(CLI::Range(0.0, 1e6));
  bool ros2 = false, no_navigation = false;
  cairn::agent::Ros2InputOptions ros2_options;
  std::vector<double> camera_mount{0.5, 0.0};
  app.add_flag("--ros2", ros2,
               "sensors from the robot's ROS 2 drivers (sensor_msgs/LaserScan, nav_msgs/Odometry, colour and aligned "
               "depth sensor_msgs/Image with CameraInfo); velocity commands out as geometry_msgs/Twist");
  app.add_option("--ros2-namespace", ros2_options.ros_namespace, "ROS 2 namespace of the robot's topics");
  app.add_option("--ros2-scan", ros2_options.scan_topic, "laser topic (relative to the namespace)");
  app.add_option("--ros2-odom", ros2_options.odom_topic, "odometry topic");
  app.add_option("--ros2-color", ros2_options.color_topic, "colour image topic (rgb8 or bgr8)");
  app.add_option("--ros2-depth", ros2_options.depth_topic, "depth image aligned to colour (16UC1 mm or 32FC1 m)");
  app.add_option("--ros2-camera-info", ros2_options.camera_info_topic, "colour camera's CameraInfo topic");
  app.add_option("--ros2-cmd-vel", ros2_options.cmd_vel_topic, "where velocity commands go");
  app.add_option("--ros2-camera-mount", camera_mount, "HEIGHT_M PITCH_DEG: the forward camera above the base")
      ->expected(2);
  app.add_flag("--ros2-reliable", ros2_options.reliable,
               "reliable scan and odometry readers: nothing lost, but only reliable publishers match (cairn_replay)");
  app.add_option("--ros2-idle-end", ros2_options.idle_end_s,
                 "end the input after this many seconds without a scan (a replayed bag; 0 = never)");
  std::optional<float> teammate_intensity;
  app.add_option("--teammate-intensity", teammate_intensity,
                 "beams at least this bright hit a teammate's reflective tape: left out of SLAM and of the "
                 "navigation map (0 = none; default 0.9 on the simulator's 0-1 scale, none with --ros2: a real "
                 "laser reports intensity in its own units)")
      ->check(CLI::Range(0.0, 1e9));
  app.add_flag("--no-navigation", no_navigation, "do not steer the robot (its data is recorded: it drove already)");
  app.add_option("--ack-timeout", node.ack_timeout_s,
                 "at the end, give up waiting for the base station's acknowledgements after this many seconds and "
                 "exit 3 naming what it lacks (0 = wait while the process runs; SIGINT/SIGTERM end it the same way)")
      ->check(CLI::Range(0.0, 1e6));
  app.add_option("--outbox", node.outbox_path,
                 "keep what this robot produces in this SQLite file until the base acknowledges it; restarted with "
                 "the same file (a crash, a power cut), the agent first resends what the earlier run left undelivered "
                 "(one file per robot; a new file for a new mission)");
  app.add_option("--log-level", log_level);
  CLI11_PARSE(app, argc, argv);
  node.link_budget_bytes_per_sec = uint32_t(link_budget_kbit * 1000.0 / 8.0);
  if (node.link_budget_bytes_per_sec > 0) node.status_period_s = std::max(node.status_period_s, 1.0);
  if (teammate_intensity && !std::isfinite(*teammate_intensity)) {
    std::cerr << "cairn_agent: --teammate-intensity: not finite\n";
    return 2;
  }
  if (ros2) {
    if (!log_path.empty()) {
      std::cerr << "cairn_agent: --ros2 and --log are two inputs: choose one\n";
      return 2;
    }
    if (!std::isfinite(camera_mount[0]) || !std::isfinite(camera_mount[1])) {
      std::cerr << "cairn_agent: --ros2-camera-mount: not finite\n";
      return 2;
    }
    ros2_options.T_base_camera = cairn::agent::forward_camera_mount(camera_mount[0], camera_mount[1]);
    node.ros2 = ros2_options;
  }
  cairn::set_log_level(log_level);
  auto log = cairn::make_logger("agent", cairn::RobotId(robot));

  cairn::agent::AgentOptions options;
  cairn::CarmenLog carmen;
  cairn::MultiRobotLog multirobot;
  try {
    if (!config_path.empty()) options = cairn::agent::load_agent_options(config_path);
    if (node.link_budget_bytes_per_sec > 0) {
      // The loop-closed poses of every keyframe (~28 B each, 14 kB after 500 keyframes): sent less
      // often on a slow radio, they stay a small share of it.
      options.keyframe_poses_min_interval_s =
          std::max(options.keyframe_poses_min_interval_s, kSlowLinkKeyframePosesInterval_s);
    }
    if (!log_path.empty() && cairn::is_multirobot_log(log_path)) {
      multirobot = cairn::read_multirobot_log(log_path);
      input.robot_log = multirobot.robot(cairn::RobotId(robot));
      if (!input.robot_log) {
        throw cairn::InputError(log_path + ": holds no records for robot " + std::to_string(robot));
      }
      log->info("{}: robot {}: {} scans, {} odometry, {} landmark observations; {} NaN beams in the log", log_path,
                robot, input.robot_log->scans.size(), input.robot_log->odometry.size(),
                input.robot_log->landmarks.size(), multirobot.stats.nan_ranges);
      if (input.robot_log->odometry.empty()) {
        log->warn("{}: no odometry for robot {}: matching with constant-velocity prediction", log_path, robot);
        options.use_odometry = false;
      }
    } else if (!log_path.empty()) {
      carmen = cairn::read_carmen_log(log_path);
      input.log = &carmen;
      if (cairn::is_corrected_log_name(log_path)) {
        // Corrected logs hold the SLAM result, not wheel odometry: do not feed it as odometry.
        log->warn("{} is a corrected log: no raw odometry, matching with constant-velocity prediction", log_path);
        input.log_options.odometry_from_log = false;
        options.use_odometry = false;
      }
      log->info("{}: {} laser records, {} odometry records, {} unknown records skipped", log_path,
                carmen.stats.laser_records, carmen.stats.odometry_records, carmen.stats.unknown_records);
    }
  } catch (const cairn::InputError& e) {
    log->error("{}", e.what());
    return 2;
  }
  options.teammate_min_intensity =
      cairn::agent::teammate_min_intensity(teammate_intensity, ros2, options.teammate_min_intensity);
  node.navigate = log_path.empty() && !no_navigation;  // a recorded robot drove already: nothing to steer
  std::string error;
  auto agent = cairn::agent::AgentNode::create(cairn::RobotId(robot), options, node, input, &error);
  if (!agent) {
    log->error("{}", error);
    return 3;
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  return agent->run(&g_stop);
}
