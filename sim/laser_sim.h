#pragma once
// Simulated planar laser: casts each beam through the floor-plan grid (exact Amanatides-Woo cell
// traversal, FloorPlan::cast_ray) from the sensor pose and adds Gaussian range noise. Beams without
// a wall within max_range_m read +inf. Walls and the other robots (vertical cylinders: circles in
// the scan plane, exact ray-circle intersection) block the laser; objects of interest are treated as
// low / off the scan plane (the scan plane is assumed above them) and are invisible to it.
#include <Eigen/Core>
#include <random>
#include <vector>

#include "common/laser_scan.h"
#include "common/se2.h"
#include "sim/floor_plan.h"
#include "sim/sim_options.h"

namespace cairn::sim {

class LaserSimulator {
 public:
  explicit LaserSimulator(const LaserOptions& options);
  /// One scan from T_world_laser; `rng` supplies the range noise (one draw per beam whatever the
  /// scene). `other_robots_m` are the centres of the other robots (never the scanning one), seen as
  /// circles of radius robot_radius_m; each beam reads the nearest of its wall and robot hits.
  LaserScan scan(const FloorPlan& plan, const SE2& T_world_laser, StampNs stamp_ns, std::mt19937_64& rng,
                 const std::vector<Eigen::Vector2d>& other_robots_m = {}, double robot_radius_m = 0.0) const;
  const LaserOptions& options() const { return options_; }

 private:
  LaserOptions options_;
  float angle_min_rad_ = 0.f;
  float angle_increment_rad_ = 0.f;
};

}  // namespace cairn::sim
