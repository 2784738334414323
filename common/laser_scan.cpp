#include "common/laser_scan.h"

#include <cmath>
#include <limits>

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

}  // namespace cairn
