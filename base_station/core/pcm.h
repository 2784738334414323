#pragma once
// Pairwise Consistency Maximization (Mangelson, Dominic, Eustice, Vasudevan, "Pairwise Consistent
// Measurement Set Maximization for Robust Multi-robot Map Merging", ICRA 2018): two inter-robot
// loop closures (a_i, b_i) and (a_j, b_j) between robots A and B are consistent when the cycle
//   T_ai_bi * T_bi_bj * T_bj_aj * T_aj_ai
// (the b and a legs from each robot's own odometry) is close to identity in the Mahalanobis sense;
// the largest set of mutually consistent closures is the maximum clique of the consistency graph
// (exact Bron-Kerbosch search with pivoting: the graphs here are small).
#include <functional>
#include <vector>

#include "common/ids.h"
#include "common/se2.h"

namespace cairn::base {

/// A verified loop closure: pose of keyframe `b` in keyframe `a`'s frame.
struct LoopClosure {
  KeyframeId a, b;
  SE2 T_a_b;
  Covariance3 covariance = Covariance3::Identity() * 1e-2;
  double score = 0.0;
};

struct PcmOptions {
  /// Chi-square gate on the 3-dof cycle error (99 %: 11.34).
  double chi2_threshold = 11.34;
  /// Odometry uncertainty grows with the distance travelled between the two keyframes of a leg.
  double odometry_sigma_xy_per_m = 0.03;
  double odometry_sigma_yaw_rad_per_m = 0.01;
  double odometry_sigma_xy_floor_m = 0.05;
  double odometry_sigma_yaw_floor_rad = 0.02;
};

/// Pose of a keyframe in its robot's local frame (the robot's own, self-consistent estimate).
using LocalPoseFn = std::function<SE2(KeyframeId)>;

/// Whether closures i and j (same robot pair, same orientation a -> b) are consistent.
bool pcm_consistent(const LoopClosure& i, const LoopClosure& j, const LocalPoseFn& local_pose,
                    const PcmOptions& options = {});

/// Indices of a maximum set of pairwise-consistent closures (sorted).
std::vector<size_t> pcm_max_clique(const std::vector<LoopClosure>& closures, const LocalPoseFn& local_pose,
                                   const PcmOptions& options = {});

}  // namespace cairn::base
