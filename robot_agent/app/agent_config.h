#pragma once
// Maps an agent YAML file onto AgentOptions (robot_agent/core/agent_options.h). Unknown sections
// are ignored; present keys are validated and errors name the file and key (InputError).
//   keyframer: {min_distance_m: 0.5, min_angle_deg: 20, max_interval_s: 5}
//   odometry:  {use: true}
//   objects:   {enabled: true}
#include <string>

#include "robot_agent/core/agent_options.h"

namespace cairn::agent {

AgentOptions load_agent_options(const std::string& yaml_path);

}  // namespace cairn::agent
