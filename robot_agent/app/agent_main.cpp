// cairn_agent: one per robot. Reads its robot's sensor topics, runs local 2D SLAM and the object
// pipeline (robot_agent/core), and publishes keyframes, objects and status to the base station.
#include <CLI/CLI.hpp>

#include "common/carmen_log.h"
#include "common/errors.h"
#include "common/huge_pages.h"
#include "common/logging.h"
#include "common/multirobot_log.h"
#include "robot_agent/app/agent_config.h"
#include "robot_agent/app/agent_node.h"

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
  app.add_option("--object-rate-limit", node.large_data_bytes_per_sec, "bytes/s for object clouds (0 = no limit)");
  app.add_option("--log-level", log_level);
  CLI11_PARSE(app, argc, argv);
  cairn::set_log_level(log_level);
  auto log = cairn::make_logger("agent", cairn::RobotId(robot));

  cairn::agent::AgentOptions options;
  cairn::CarmenLog carmen;
  cairn::MultiRobotLog multirobot;
  try {
    if (!config_path.empty()) options = cairn::agent::load_agent_options(config_path);
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
  node.navigate = log_path.empty();  // a recorded robot drove already: nothing to steer
  std::string error;
  auto agent = cairn::agent::AgentNode::create(cairn::RobotId(robot), options, node, input, &error);
  if (!agent) {
    log->error("{}", error);
    return 3;
  }
  return agent->run();
}
