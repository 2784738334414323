#include "sim/laser_sim.h"

#include <cmath>
#include <limits>

namespace cairn::sim {

LaserSimulator::LaserSimulator(const LaserOptions& options) : options_(options) {
  const double fov_rad = options_.fov_deg * M_PI / 180.0;
  const int n = std::max(1, options_.beams);
  if (options_.fov_deg >= 360.0 - 1e-9) {
    angle_min_rad_ = float(-M_PI);
    angle_increment_rad_ = float(2.0 * M_PI / n);
  } else {
    angle_min_rad_ = float(-0.5 * fov_rad);
    angle_increment_rad_ = n > 1 ? float(fov_rad / (n - 1)) : 0.f;
  }
}

LaserScan LaserSimulator::scan(const FloorPlan& plan, const SE2& T_world_laser, StampNs stamp_ns,
                               std::mt19937_64& rng) const {
  LaserScan out;
  out.stamp_ns = stamp_ns;
  out.angle_min_rad = angle_min_rad_;
  out.angle_increment_rad = angle_increment_rad_;
  out.range_min_m = float(options_.min_range_m);
  out.range_max_m = float(options_.max_range_m);
  out.ranges_m.resize(size_t(std::max(1, options_.beams)));
  std::normal_distribution<double> noise(0.0, 1.0);
  for (size_t i = 0; i < out.ranges_m.size(); ++i) {
    const double angle = T_world_laser.yaw() + double(angle_min_rad_) + double(i) * angle_increment_rad_;
    const RayHit hit = plan.cast_ray(T_world_laser.translation(), angle, options_.max_range_m);
    const double n = noise(rng);  // drawn for every beam: the stream does not depend on the scene
    if (!hit.hit) {
      out.ranges_m[i] = std::numeric_limits<float>::infinity();
      continue;
    }
    double r = hit.range_m + options_.noise_sd_m * n;
    // Noise must not turn a return into "no return" at either end of the range.
    r = std::clamp(r, options_.min_range_m + 1e-3, options_.max_range_m - 1e-3);
    out.ranges_m[i] = float(r);
  }
  return out;
}

}  // namespace cairn::sim
