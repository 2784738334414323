#include "robot_agent/core/navigation/nav_map.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cairn::agent {
namespace {

OccupancyGridOptions grid_options(const NavMapOptions& o) {
  OccupancyGridOptions g;
  g.resolution_m = o.resolution_m;
  g.hit_log_odds = o.hit_log_odds;
  g.miss_log_odds = o.miss_log_odds;
  g.min_log_odds = o.min_log_odds;
  g.max_log_odds = o.max_log_odds;
  g.max_range_m = o.max_range_m;
  return g;
}

}  // namespace

NavMap::NavMap(const NavMapOptions& options) : options_(options), grid_(grid_options(options)) {}

void NavMap::insert(const SE2& T_local_base, const LaserScan& scan) {
  // Hits as the SLAM front end sees them; beams without a return (+inf or at/over range_max) clear
  // free space up to no_return_clear_m, as the base's global map does (global_map_renderer.cpp);
  // a teammate's beam clears up to it.
  LaserScan walls = scan;
  std::vector<Eigen::Vector2f> no_return;
  const float clear_m = float(std::min<double>(scan.range_max_m, options_.no_return_clear_m));
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const float r = scan.ranges_m[i];
    if (std::isnan(r)) continue;
    const float a = beam_angle_rad(scan, i);
    if (on_teammate(scan, i, options_.teammate_min_intensity) && r < scan.range_max_m) {
      walls.ranges_m[i] = std::numeric_limits<float>::quiet_NaN();  // not a wall
      const float to_m = r - float(options_.teammate_clear_short_m);
      if (to_m > 0.f) no_return.emplace_back(to_m * std::cos(a), to_m * std::sin(a));
    } else if (r >= scan.range_max_m && clear_m > 0.f) {
      no_return.emplace_back(clear_m * std::cos(a), clear_m * std::sin(a));
    }
  }
  grid_.insert_scan(T_local_base, scan_to_points(walls), no_return);
  ++scans_;
}

}  // namespace cairn::agent
