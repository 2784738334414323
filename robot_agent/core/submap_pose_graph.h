#pragma once
// SubmapPoseGraph: one robot's own sparse pose graph over its submaps and scan nodes (the base
// station's multi-robot keyframe graph is base::KeyframePoseGraph). After Cartographer's PoseGraph2D /
// OptimizationProblem2D ("sparse pose adjustment", Konolige et al. 2010; Hess et al. 2016 Sec. V-A):
// every node is tied to the submaps it was inserted into (intra-submap constraints from local SLAM)
// and to its successor, and loop-closure constraints tie nodes to older submaps. Optimised with
// Ceres, robust (Huber) loss on loop closures, the first submap held fixed. Every edge is the shared
// SE2 relative-pose residual (common/se2_relative_pose_residual.h) with the yaw error wrapped as SE2
// wraps it (YawWrap::kFmod).
#include <Eigen/Core>
#include <array>
#include <vector>

#include "common/se2.h"

namespace cairn::agent {

struct SubmapPoseGraphOptions {
  /// Weights are 1/sigma of each residual component (metres, radians).
  double intra_translation_weight = 1.0 / 0.05;
  double intra_rotation_weight = 1.0 / 0.01;
  double successive_translation_weight = 1.0 / 0.02;
  double successive_rotation_weight = 1.0 / 0.005;
  double loop_translation_weight = 1.0 / 0.02;
  double loop_rotation_weight = 1.0 / 0.005;
  double loop_huber_scale = 2.0;  ///< in weighted-residual units (sigmas)
  int max_num_iterations = 30;
};

struct SubmapPoseGraphConstraint {
  enum class Kind { kIntraSubmap, kLoopClosure };
  int submap = 0;
  int node = 0;
  SE2 T_submap_node;
  Kind kind = Kind::kIntraSubmap;
  double score = 0.0;  ///< match score of a loop closure
  /// When set, the residual is sqrt_information * (x_m, y_m, yaw_rad) error in the submap frame
  /// (upper-left 2x2: translation, may be anisotropic) instead of the options' fixed weights.
  bool has_sqrt_information = false;
  Eigen::Matrix3d sqrt_information = Eigen::Matrix3d::Identity();
};

/// Square-root information of a match from its covariance (translation block rotated by
/// `R_frame_match`, i.e. expressed in that frame): the best-determined translation direction keeps
/// `translation_weight` (1/m) and a direction whose standard deviation is k times larger gets
/// translation_weight / k, at least translation_weight * min_weight_ratio; yaw keeps
/// `rotation_weight`. So a corner match stays isotropic while a corridor match is weak along the
/// corridor (Olson 2009 Sec. IV, Censi 2007: the match covariance shapes the constraint).
Eigen::Matrix3d anisotropic_sqrt_information(const Eigen::Matrix3d& covariance, double yaw_frame_match_rad,
                                             double translation_weight, double rotation_weight,
                                             double min_weight_ratio);

class SubmapPoseGraph {
 public:
  explicit SubmapPoseGraph(const SubmapPoseGraphOptions& options = {});

  int add_submap(const SE2& T_global_submap);
  /// A node; consecutive nodes are tied by their local-SLAM relative pose `T_prev_node`, weighted by
  /// `successive_sqrt_information` (in the previous node's frame) when given, else by the options.
  int add_node(const SE2& T_global_node, const SE2& T_local_node,
               const Eigen::Matrix3d* successive_sqrt_information = nullptr);
  void add_constraint(const SubmapPoseGraphConstraint& c);

  /// Runs Ceres (at most `max_num_iterations`, or the options' when <= 0); returns false when the
  /// solver reports an unusable solution (poses unchanged).
  bool optimize(int max_num_iterations = 0);

  const SE2& submap_pose(int i) const { return submaps_[size_t(i)]; }
  const SE2& node_pose(int i) const { return nodes_[size_t(i)]; }
  int num_submaps() const { return int(submaps_.size()); }
  int num_nodes() const { return int(nodes_.size()); }
  const std::vector<SubmapPoseGraphConstraint>& constraints() const { return constraints_; }
  int num_loop_closures() const { return num_loops_; }

 private:
  SubmapPoseGraphOptions options_;
  std::vector<SE2> submaps_;
  std::vector<SE2> nodes_;
  std::vector<SE2> local_nodes_;                              ///< local-SLAM poses, for successive-node constraints
  std::vector<Eigen::Matrix3d> successive_sqrt_information_;  ///< per node (from the second)
  std::vector<bool> has_successive_sqrt_information_;
  std::vector<SubmapPoseGraphConstraint> constraints_;
  int num_loops_ = 0;
};

}  // namespace cairn::agent
