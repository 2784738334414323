#pragma once
// A planar laser scan, its conversion to points with bad readings filtered and counted, and the
// voxel thinning of those points.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "common/time.h"

namespace cairn {

struct LaserScan {
  StampNs stamp_ns = 0;
  float angle_min_rad = 0.f;        ///< angle of ranges_m[0] in the sensor frame (CCW, 0 = forward)
  float angle_increment_rad = 0.f;  ///< CCW step between beams
  float range_min_m = 0.05f;        ///< readings at or below this are "no return"
  float range_max_m = 30.f;         ///< readings at or above this are "no return"
  std::vector<float> ranges_m;
  /// Per beam, same length as ranges_m, or empty when the sensor gives none. The team's robots carry
  /// retro-reflective tape: beams that hit a teammate come back brighter than any wall
  /// (on_teammate; robot_agent's AgentOptions::teammate_min_intensity leaves them out of SLAM).
  std::vector<float> intensities;
};

/// Why readings were dropped; reported so bad sensors are visible, never silently swallowed.
struct ScanFilterStats {
  int valid = 0;
  int nan_or_inf = 0;  ///< NaN or -inf: a broken reading
  int too_close = 0;   ///< zero or below range_min_m
  int max_range = 0;   ///< at or beyond range_max_m, or +inf: no return
  ScanFilterStats& operator+=(const ScanFilterStats& o) {
    valid += o.valid;
    nan_or_inf += o.nan_or_inf;
    too_close += o.too_close;
    max_range += o.max_range;
    return *this;
  }
};

/// Endpoints of the valid beams in the sensor frame (metres).
std::vector<Eigen::Vector2f> scan_to_points(const LaserScan& scan, ScanFilterStats* stats = nullptr);

/// Keeps the first point per cell of `voxel_m` (scan order), so dense scans cost less to match
/// (0 or less: all points).
std::vector<Eigen::Vector2f> voxel_filter_2d(const std::vector<Eigen::Vector2f>& points, double voxel_m);

/// Angle of beam i.
inline float beam_angle_rad(const LaserScan& scan, size_t i) {
  return scan.angle_min_rad + float(i) * scan.angle_increment_rad;
}

/// Beam i came back from a teammate's reflective tape: at least `min_intensity` bright. None is
/// when min_intensity is 0 or the scan has no intensities (SLAM and the navigation map ask alike).
inline bool on_teammate(const LaserScan& scan, size_t i, float min_intensity) {
  return min_intensity > 0.f && scan.intensities.size() == scan.ranges_m.size() && scan.intensities[i] >= min_intensity;
}

}  // namespace cairn
