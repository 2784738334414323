#include "sim/laser_sim.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace cairn::sim {
namespace {

/// Distance along the unit ray from `from` to where it enters the circle, if it does ahead of `from`
/// and within max_range_m.
std::optional<double> ray_circle(const Eigen::Vector2d& from, const Eigen::Vector2d& unit_dir,
                                 const Eigen::Vector2d& center, double radius, double max_range_m) {
  const Eigen::Vector2d w = center - from;
  const double b = w.dot(unit_dir);
  const double disc = b * b - (w.squaredNorm() - radius * radius);
  if (disc < 0.0) return std::nullopt;
  const double t = b - std::sqrt(disc);
  if (t <= 0.0 || t > max_range_m) return std::nullopt;  // behind, around the sensor, or too far
  return t;
}

}  // namespace

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

LaserScan LaserSimulator::scan(const FloorPlan& plan, const SE2& T_world_laser, StampNs stamp_ns, std::mt19937_64& rng,
                               const std::vector<Eigen::Vector2d>& other_robots_m, double robot_radius_m) const {
  LaserScan out;
  out.stamp_ns = stamp_ns;
  out.angle_min_rad = angle_min_rad_;
  out.angle_increment_rad = angle_increment_rad_;
  out.range_min_m = float(options_.min_range_m);
  out.range_max_m = float(options_.max_range_m);
  out.ranges_m.resize(size_t(std::max(1, options_.beams)));
  out.intensities.assign(out.ranges_m.size(), 0.f);
  const Eigen::Vector2d origin = T_world_laser.translation();
  std::vector<Eigen::Vector2d> near_robots;  // only those a beam can reach
  for (const Eigen::Vector2d& c : other_robots_m) {
    if (robot_radius_m > 0.0 && (c - origin).norm() - robot_radius_m < options_.max_range_m) near_robots.push_back(c);
  }
  std::normal_distribution<double> noise(0.0, 1.0);
  for (size_t i = 0; i < out.ranges_m.size(); ++i) {
    const double angle = T_world_laser.yaw() + double(angle_min_rad_) + double(i) * angle_increment_rad_;
    const RayHit hit = plan.cast_ray(origin, angle, options_.max_range_m);
    const double n = noise(rng);  // drawn for every beam: the stream does not depend on the scene
    double range_m = hit.hit ? hit.range_m : std::numeric_limits<double>::infinity();
    bool teammate = false;
    const Eigen::Vector2d dir(std::cos(angle), std::sin(angle));
    for (const Eigen::Vector2d& c : near_robots) {
      const auto t = ray_circle(origin, dir, c, robot_radius_m, options_.max_range_m);
      if (t && *t < range_m) range_m = *t, teammate = true;
    }
    if (!std::isfinite(range_m)) {
      out.ranges_m[i] = std::numeric_limits<float>::infinity();
      continue;
    }
    double r = range_m + options_.noise_sd_m * n;
    // Noise must not turn a return into "no return" at either end of the range.
    r = std::clamp(r, options_.min_range_m + 1e-3, options_.max_range_m - 1e-3);
    out.ranges_m[i] = float(r);
    out.intensities[i] = teammate ? options_.teammate_intensity : options_.surface_intensity;
  }
  return out;
}

}  // namespace cairn::sim
