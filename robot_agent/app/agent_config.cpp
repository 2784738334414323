#include "robot_agent/app/agent_config.h"

#include <cmath>

#include "common/yaml_config.h"

namespace cairn::agent {

AgentOptions load_agent_options(const std::string& yaml_path) {
  const YamlConfig cfg = YamlConfig::load(yaml_path);
  AgentOptions o;
  cfg.allow_only({"keyframer", "odometry", "objects"});
  if (cfg.has("keyframer")) {
    const YamlConfig k = cfg["keyframer"];
    k.allow_only({"min_distance_m", "min_angle_deg", "max_interval_s"});
    o.keyframer.min_distance_m = k.get("min_distance_m", o.keyframer.min_distance_m);
    o.keyframer.min_angle_rad = k.get("min_angle_deg", o.keyframer.min_angle_rad * 180.0 / M_PI) * M_PI / 180.0;
    o.keyframer.max_interval_s = k.get("max_interval_s", o.keyframer.max_interval_s);
    if (!(o.keyframer.min_distance_m > 0)) k.fail("min_distance_m", "must be > 0");
    if (!(o.keyframer.min_angle_rad > 0)) k.fail("min_angle_deg", "must be > 0");
    if (!(o.keyframer.max_interval_s > 0)) k.fail("max_interval_s", "must be > 0");
  }
  if (cfg.has("odometry")) {
    cfg["odometry"].allow_only({"use"});
    o.use_odometry = cfg["odometry"].get("use", o.use_odometry);
  }
  if (cfg.has("objects")) {
    cfg["objects"].allow_only({"enabled"});
    o.enable_objects = cfg["objects"].get("enabled", o.enable_objects);
  }
  return o;
}

}  // namespace cairn::agent
