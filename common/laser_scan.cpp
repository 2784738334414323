#include "common/laser_scan.h"

#include <cmath>
#include <limits>
#include <unordered_set>

namespace cairn {

std::vector<Eigen::Vector2f> scan_to_points(const LaserScan& scan, ScanFilterStats* stats) {
  ScanFilterStats local;
  std::vector<Eigen::Vector2f> points;
  points.reserve(scan.ranges_m.size());
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const float r = scan.ranges_m[i];
    if (std::isnan(r) || r == -std::numeric_limits<float>::infinity()) {
      ++local.nan_or_inf;
      continue;
    }
    if (r <= scan.range_min_m) {
      ++local.too_close;
      continue;
    }
    if (r >= scan.range_max_m) {
      ++local.max_range;
      continue;
    }
    const float a = beam_angle_rad(scan, i);
    points.emplace_back(r * std::cos(a), r * std::sin(a));
    ++local.valid;
  }
  if (stats) *stats += local;
  return points;
}

std::vector<Eigen::Vector2f> voxel_filter_2d(const std::vector<Eigen::Vector2f>& points, double voxel_m) {
  if (voxel_m <= 0.0) return points;
  std::unordered_set<int64_t> seen;
  std::vector<Eigen::Vector2f> out;
  out.reserve(points.size());
  for (const auto& p : points) {
    const int64_t cx = int64_t(std::floor(p.x() / voxel_m)), cy = int64_t(std::floor(p.y() / voxel_m));
    // Shifted as unsigned: a left shift of a negative value is undefined behaviour.
    if (seen.insert(int64_t((uint64_t(cx) << 32) ^ (uint64_t(cy) & 0xffffffffu))).second) out.push_back(p);
  }
  return out;
}

}  // namespace cairn
