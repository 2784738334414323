#include "common/odometry_noise.h"

#include <cmath>
#include <random>

namespace cairn {

std::vector<SE2> add_odometry_noise(const std::vector<SE2>& poses, const OdometryNoiseOptions& o) {
  std::vector<SE2> out;
  if (poses.empty()) return out;
  std::mt19937 rng(o.seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  out.reserve(poses.size());
  out.push_back(poses.front());
  for (size_t i = 1; i < poses.size(); ++i) {
    const SE2 d = poses[i - 1].between(poses[i]);
    const double dist_m = d.translation().norm();
    const double scale = 1.0 + o.translation_noise_per_m * n01(rng);
    // Lateral error as large as the longitudinal one, both proportional to the step length.
    const Eigen::Vector2d t =
        scale * d.translation() + o.translation_noise_per_m * n01(rng) * Eigen::Vector2d(-d.y(), d.x());
    const double yaw_sigma = o.rotation_noise_rad_per_m * dist_m + o.rotation_noise_rad_per_rad * std::abs(d.yaw());
    out.push_back(out.back() * SE2(t, d.yaw() + yaw_sigma * n01(rng)));
  }
  return out;
}

}  // namespace cairn
