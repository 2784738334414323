#pragma once
// Scan Context for 2D laser scans (Kim & Kim, "Scan Context: Egocentric Spatial Descriptor for
// Place Recognition within 3D Point Cloud Map", IROS 2018), adapted to the plane: a polar grid of
// rings x sectors around the sensor; each bin holds log(1 + number of points). The ring key
// (per-ring mean) is rotation-invariant and used for a fast nearest-neighbour pre-selection; the
// full distance is the column-shift-minimised mean cosine distance over columns seen by both
// descriptors (so partial fields of view compare fairly), and the best shift estimates the yaw.
// The agent computes it per keyframe (from the keyframe's scan, or from the points of its last few
// keyframes in the keyframe frame for narrow lasers) and sends it; the base recomputes it when absent.
#include <Eigen/Core>
#include <vector>

#include "common/laser_scan.h"

namespace cairn {

struct ScanContextOptions {
  int num_rings = 20;
  int num_sectors = 60;
  double max_range_m = 20.0;
};

/// Flat descriptor, ring-major (ring r, sector s at r * num_sectors + s); sector 0 starts at -pi
/// in the sensor frame, counter-clockwise. Empty when there are no points.
std::vector<float> compute_scan_context(const std::vector<Eigen::Vector2f>& points_sensor,
                                        const ScanContextOptions& options = {});
std::vector<float> compute_scan_context(const LaserScan& scan, const ScanContextOptions& options = {});

/// Rotation-invariant ring key (mean of each ring), num_rings values.
std::vector<float> scan_context_ring_key(const std::vector<float>& descriptor, const ScanContextOptions& options = {});

struct ScanContextMatch {
  double distance = 1.0;  ///< 0 (identical) .. 1 (nothing in common)
  int shift_sectors = 0;
  double yaw_rad = 0.0;   ///< estimated yaw of b's sensor frame in a's (T_a_b.yaw)
  bool valid = false;     ///< false when sizes mismatch or no common column
};

/// Distance between two descriptors, minimised over all column shifts.
ScanContextMatch scan_context_distance(const std::vector<float>& a, const std::vector<float>& b,
                                       const ScanContextOptions& options = {});

}  // namespace cairn
