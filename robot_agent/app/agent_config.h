#pragma once
// Maps an agent YAML file onto AgentOptions (robot_agent/core/agent_options.h). Unknown sections
// are ignored; present keys are validated and errors name the file and key (InputError).
//   keyframer: {min_distance_m: 0.5, min_angle_deg: 20, max_interval_s: 5}
//   odometry:  {use: true}
//   objects:   {enabled: true}
#include <optional>
#include <string>

#include "robot_agent/core/agent_options.h"

namespace cairn::agent {

AgentOptions load_agent_options(const std::string& yaml_path);

/// How bright a beam on a teammate's reflective tape is (AgentOptions::teammate_min_intensity, for
/// SLAM and the navigation map alike): `given` (cairn_agent --teammate-intensity) wins; else none
/// (0) for a ROS 2 robot's laser, whose intensities are in its own units (a bright one would have
/// every beam taken for a teammate and nothing left to map); else `configured` (the simulator's 0-1).
float teammate_min_intensity(std::optional<float> given, bool ros2_input, float configured);

}  // namespace cairn::agent
