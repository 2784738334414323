#include "sim/radio_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cairn::sim {

int walls_crossed(const FloorPlan& plan, const Eigen::Vector2d& a_m, const Eigen::Vector2d& b_m) {
  const double length_m = (b_m - a_m).norm();
  const int samples = std::max(1, int(std::ceil(length_m / (0.5 * plan.resolution_m()))));
  int walls = 0;
  bool inside = false;
  for (int i = 0; i <= samples; ++i) {
    const bool wall = plan.wall_at(a_m + (b_m - a_m) * (double(i) / samples));
    if (wall && !inside) ++walls;
    inside = wall;
  }
  return walls;
}

RadioReading radio_reading(const FloorPlan& plan, const RadioOptions& options, const Eigen::Vector2d& robot_m) {
  RadioReading best{-std::numeric_limits<double>::infinity(), 0};
  for (const Eigen::Vector2d& antenna_m : options.antennas_m) {
    // Closer than 1 m the model's reference distance stands (no gain from coming closer).
    const double d_m = std::max(1.0, (robot_m - antenna_m).norm());
    RadioReading r;
    r.walls = walls_crossed(plan, antenna_m, robot_m);
    r.received_dbm = options.tx_power_dbm - options.loss_at_1m_db -
                     10.0 * options.path_loss_exponent * std::log10(d_m) - options.wall_loss_db * r.walls;
    if (r.received_dbm > best.received_dbm) best = r;
  }
  return best;
}

bool RadioLink::update(const RadioReading& reading, StampNs now_ns) {
  if (up_) {
    if (reading.received_dbm >= options_.sensitivity_dbm) return false;
    up_ = false;
    in_range_since_ns_ = -1;
    return true;
  }
  if (reading.received_dbm < options_.sensitivity_dbm + options_.hysteresis_db) {
    in_range_since_ns_ = -1;
    return false;
  }
  if (in_range_since_ns_ < 0) in_range_since_ns_ = now_ns;
  up_ = now_ns - in_range_since_ns_ >= sec_to_ns(options_.reconnect_s);
  return up_;
}

std::vector<RadioSample> RadioLinks::update(StampNs now_ns,
                                            const std::vector<std::pair<RobotId, Eigen::Vector2d>>& robots_m) {
  std::vector<RadioSample> out;
  if (now_ns < next_due_ns_) return out;
  next_due_ns_ = now_ns + sec_to_ns(options_.period_s);
  for (const auto& entry : robots_m) {
    const RobotId robot = entry.first;
    auto it = std::find_if(links_.begin(), links_.end(), [robot](const auto& l) { return l.first == robot; });
    if (it == links_.end()) it = links_.insert(links_.end(), {robot, RadioLink(options_)});
    RadioSample s{robot, now_ns, radio_reading(plan_, options_, entry.second)};
    s.changed = it->second.update(s.reading, now_ns);
    s.up = it->second.up();
    out.push_back(s);
  }
  return out;
}

}  // namespace cairn::sim
