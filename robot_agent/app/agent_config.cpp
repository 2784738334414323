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
    // Its noise (variance per metre / radian) sets the covariances of keyframes made from odometry
    // alone while the laser is silent (robot_agent/core/dead_reckoning.h).
    const YamlConfig od = cfg["odometry"];
    od.allow_only({"use", "dead_reckon_without_laser", "laser_timeout_s", "translation_variance_m2_per_m",
                   "rotation_variance_rad2_per_m", "rotation_variance_rad2_per_rad"});
    o.use_odometry = od.get("use", o.use_odometry);
    o.dead_reckon_without_laser = od.get("dead_reckon_without_laser", o.dead_reckon_without_laser);
    DeadReckoningOptions& d = o.dead_reckoning;
    const auto in_range = [&od](const std::string& key, double value, double lo, double hi, bool lo_open) {
      const double v = od.get(key, value);
      if (!(lo_open ? v > lo : v >= lo) || !(v <= hi)) {
        od.fail(key, "must be in " + std::string(lo_open ? "(" : "[") + std::to_string(lo) + ", " + std::to_string(hi) +
                         "] (got " + std::to_string(v) + ")");
      }
      return v;
    };
    d.laser_timeout_s = in_range("laser_timeout_s", d.laser_timeout_s, 0.0, 60.0, true);
    d.translation_variance_m2_per_m =
        in_range("translation_variance_m2_per_m", d.translation_variance_m2_per_m, 0, 1, false);
    d.rotation_variance_rad2_per_m =
        in_range("rotation_variance_rad2_per_m", d.rotation_variance_rad2_per_m, 0, 1, false);
    d.rotation_variance_rad2_per_rad =
        in_range("rotation_variance_rad2_per_rad", d.rotation_variance_rad2_per_rad, 0, 1, false);
  }
  if (cfg.has("objects")) {
    cfg["objects"].allow_only({"enabled"});
    o.enable_objects = cfg["objects"].get("enabled", o.enable_objects);
  }
  return o;
}

float teammate_min_intensity(std::optional<float> given, bool ros2_input, float configured) {
  if (given) return *given;
  return ros2_input ? 0.f : configured;
}

}  // namespace cairn::agent
