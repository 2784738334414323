#pragma once
// Scan Context for 2D laser scans (Kim & Kim, "Scan Context: Egocentric Spatial Descriptor for
// Place Recognition within 3D Point Cloud Map", IROS 2018), adapted to the plane: a polar grid of
// rings x sectors around the sensor; each bin holds log(1 + number of points). The ring key
// (per-ring mean) is rotation-invariant and used for a fast nearest-neighbour pre-selection; the
// full distance is the column-shift-minimised mean cosine distance over columns seen by both
// descriptors (so partial fields of view compare fairly), and the best shift estimates the yaw.
// The agent computes it per keyframe with compute_keyframe_scan_context (the points of the keyframe
// and of its last few predecessors, in the keyframe's frame: narrow lasers see too little alone)
// and sends it in Keyframe::place_descriptor; the base recomputes it with the same function when
// absent. Both sides use ScanContextOptions{} (defaults below, the one place they are set).
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/keyframe.h"
#include "common/laser_scan.h"

namespace cairn {

struct ScanContextOptions {
  int num_rings = 20;
  int num_sectors = 60;
  double max_range_m = 20.0;
  /// Keyframes merged into a keyframe's descriptor: the keyframe and its predecessors (seq - 1, ...).
  /// 15 (about 7 m of travel at 0.5 m keyframe spacing) gives a 180-degree laser a near 360-degree
  /// view of the place: on the raw MIT CSAIL split (SICK, 180 deg) it cut the verified wrong
  /// inter-robot candidates from 197 to 89 at equal recall (tests/multirobot funnel). It is not the
  /// default: with 360-degree lasers (the simulated worlds) it linked fewer robots (collapsed demo:
  /// 1 of 4 instead of 3 of 4) and made the base's verifications several times slower.
  int descriptor_keyframes = 3;
};

/// Flat descriptor, ring-major (ring r, sector s at r * num_sectors + s); sector 0 starts at -pi
/// in the sensor frame, counter-clockwise. Empty when there are no points.
std::vector<float> compute_scan_context(const std::vector<Eigen::Vector2f>& points_sensor,
                                        const ScanContextOptions& options = {});
std::vector<float> compute_scan_context(const LaserScan& scan, const ScanContextOptions& options = {});

/// Descriptor of keyframe `kf`: the points of its scan and of its robot's predecessors with seq in
/// [kf.seq - descriptor_keyframes + 1, kf.seq - 1] found in `recent` (others are ignored; missing
/// ones are skipped), expressed in kf's base frame through the keyframes' local poses.
std::vector<float> compute_keyframe_scan_context(const Keyframe& kf, const std::vector<const Keyframe*>& recent,
                                                 const ScanContextOptions& options = {});
/// Whether `descriptor` has the size `options` give (else it was computed with other options).
bool scan_context_size_ok(const std::vector<float>& descriptor, const ScanContextOptions& options = {});

/// Wire form of a descriptor: bins quantised to 1/32 (log counts stay below 8) as bytes, then zstd.
/// 1200 floats (4.8 kB) become ~0.2-0.4 kB. decode returns nullopt for corrupt bytes.
std::vector<uint8_t> encode_scan_context(const std::vector<float>& descriptor);
std::optional<std::vector<float>> decode_scan_context(const std::vector<uint8_t>& bytes, std::string* error = nullptr);

/// Rotation-invariant ring key (mean of each ring), num_rings values.
std::vector<float> scan_context_ring_key(const std::vector<float>& descriptor, const ScanContextOptions& options = {});

struct ScanContextMatch {
  double distance = 1.0;  ///< 0 (identical) .. 1 (nothing in common)
  int shift_sectors = 0;
  double yaw_rad = 0.0;  ///< estimated yaw of b's sensor frame in a's (T_a_b.yaw)
  bool valid = false;    ///< false when sizes mismatch or no common column
};

/// Distance between two descriptors, minimised over all column shifts.
ScanContextMatch scan_context_distance(const std::vector<float>& a, const std::vector<float>& b,
                                       const ScanContextOptions& options = {});

}  // namespace cairn
