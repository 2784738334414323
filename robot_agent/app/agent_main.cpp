// cairn_agent: one per robot. Reads its robot's sensor topics, runs local 2D SLAM and the object
// pipeline (robot_agent/core), and publishes keyframes, objects and status to the base station.
#include <CLI/CLI.hpp>

#include "common/errors.h"
#include "common/logging.h"
#include "robot_agent/app/agent_config.h"
#include "robot_agent/app/agent_node.h"

int main(int argc, char** argv) {
  CLI::App app{"Cairn robot agent"};
  int robot = -1;
  std::string config_path, log_level = "info";
  cairn::agent::AgentNodeOptions node;
  app.add_option("--robot", robot, "robot id")->required()->check(CLI::Range(0, 1000));
  app.add_option("--domain", node.domain_id, "DDS domain id")->check(CLI::Range(0, 232));
  app.add_option("--config", config_path, "agent YAML (keyframer, odometry, objects)");
  app.add_option("--object-rate-limit", node.large_data_bytes_per_sec, "bytes/s for object clouds (0 = no limit)");
  app.add_option("--log-level", log_level);
  CLI11_PARSE(app, argc, argv);
  cairn::set_log_level(log_level);
  auto log = cairn::make_logger("agent", cairn::RobotId(robot));

  cairn::agent::AgentOptions options;
  try {
    if (!config_path.empty()) options = cairn::agent::load_agent_options(config_path);
  } catch (const cairn::InputError& e) {
    log->error("{}", e.what());
    return 2;
  }
  std::string error;
  auto agent = cairn::agent::AgentNode::create(cairn::RobotId(robot), options, node, &error);
  if (!agent) {
    log->error("{}", error);
    return 3;
  }
  return agent->run();
}
