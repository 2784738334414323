#pragma once
// Timestamped 2D trajectories: CSV I/O and accuracy metrics (ATE after a best SE2 alignment, RPE).
#include <optional>
#include <string>
#include <vector>

#include "common/se2.h"
#include "common/time.h"

namespace cairn {

struct StampedPose {
  StampNs stamp_ns = 0;
  SE2 pose;
};
using Trajectory = std::vector<StampedPose>;

/// CSV with header `stamp_ns,x_m,y_m,yaw_rad`. Throws InputError naming the line when malformed.
Trajectory read_trajectory_csv(const std::string& path);
/// Returns false on I/O failure.
bool write_trajectory_csv(const std::string& path, const Trajectory& trajectory);

/// Pose at `stamp_ns` by interpolation; nullopt outside the trajectory's time span
/// (or across a gap longer than max_gap_ns). `trajectory` must be sorted by stamp.
std::optional<SE2> interpolate_pose(const Trajectory& trajectory, StampNs stamp_ns, StampNs max_gap_ns = 2 * kNsPerSec);

struct TrajectoryErrorStats {
  int matched = 0;  ///< poses compared
  double ate_rmse_m = 0, ate_mean_m = 0, ate_max_m = 0;
  double rpe_trans_mean_m = 0;  ///< per-step relative error over consecutive estimate poses
  double rpe_rot_mean_rad = 0;
  SE2 T_reference_estimate;  ///< the alignment applied to the estimate
};

struct TrajectoryErrorOptions {
  bool align = true;  ///< best SE2 (Umeyama, no scale) alignment before ATE
  StampNs max_gap_ns = 2 * kNsPerSec;
};

/// Compares `estimate` to `reference` at the estimate's stamps (reference interpolated).
/// nullopt when fewer than 2 poses can be matched.
std::optional<TrajectoryErrorStats> trajectory_error(const Trajectory& estimate, const Trajectory& reference,
                                                     const TrajectoryErrorOptions& options = {});

/// Closed-form least-squares rigid alignment: returns T minimising sum |ref_i - T * est_i|^2.
SE2 align_points_2d(const std::vector<Eigen::Vector2d>& est, const std::vector<Eigen::Vector2d>& ref);

}  // namespace cairn
