#pragma once
// Keyframe selection by travelled distance, turned angle and elapsed time (DESIGN.md "Robot agent"
// 1-2; the usual pose-graph SLAM front-end rule, e.g. Cartographer's node insertion with a motion
// filter). Each keyframe carries its local pose, the relative pose from the previous keyframe with
// a covariance, and the scan, for the base station's pose graph.
#include <optional>

#include "common/ids.h"
#include "common/keyframe.h"
#include "common/laser_scan.h"
#include "common/se2.h"

namespace cairn::agent {

struct KeyframerOptions {
  double min_distance_m = 0.5;
  double min_angle_rad = 20.0 * M_PI / 180.0;
  double max_interval_s = 5.0;
  /// Edge covariance = match covariances of both ends + this floor + drift growing with distance.
  double edge_translation_floor_m2 = 1e-4;
  double edge_rotation_floor_rad2 = 1e-4;
  double edge_translation_variance_per_m = 1e-4;  ///< m^2 per metre travelled
  double edge_rotation_variance_per_rad = 1e-4;   ///< rad^2 per radian turned
};

/// Covariance of A*B from those of A and B (first-order, independent).
Covariance3 compose_covariance(const SE2& A, const Covariance3& cov_A, const SE2& B, const Covariance3& cov_B);

class Keyframer {
 public:
  Keyframer(RobotId robot, const KeyframerOptions& options = {});

  /// Offers a matched scan; returns a keyframe when a threshold is crossed (always for the first).
  std::optional<Keyframe> add(const LaserScan& scan, const SE2& T_local_base, const Covariance3& covariance);
  /// Offers a pose from wheel odometry alone (the laser is silent): a keyframe without scan when a
  /// threshold is crossed, its edge covariance `odometry_covariance` (the odometry increment's since
  /// the last keyframe, in that keyframe's frame) plus the last match covariance, if any.
  std::optional<Keyframe> add_dead_reckoned(StampNs stamp_ns, const SE2& T_local_base,
                                            const Covariance3& odometry_covariance);

  bool has_keyframe() const { return last_.has_value(); }
  /// The latest emitted keyframe (requires has_keyframe()).
  const Keyframe& last() const { return *last_; }
  int32_t next_seq() const { return next_seq_; }

 private:
  bool should_emit(StampNs stamp_ns, const SE2& pose) const;
  /// The next keyframe at `T_local_base`: its pose covariance is the last one's composed with
  /// `edge_covariance` (for the first keyframe, `edge_covariance` is its pose covariance).
  Keyframe emit(const LaserScan& scan, const SE2& T_local_base, const Covariance3& edge_covariance);

  RobotId robot_;
  KeyframerOptions options_;
  int32_t next_seq_ = 0;
  std::optional<Keyframe> last_;
  Covariance3 last_match_covariance_ = Covariance3::Zero();
};

}  // namespace cairn::agent
