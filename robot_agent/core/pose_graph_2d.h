#pragma once
// Sparse pose graph over submaps and scan nodes (Cartographer's PoseGraph2D / OptimizationProblem2D,
// "sparse pose adjustment", Konolige et al. 2010; Hess et al. 2016 Sec. V-A): every node is tied to
// the submaps it was inserted into (intra-submap constraints from local SLAM) and to its successor,
// and loop-closure constraints tie nodes to older submaps. Optimised with Ceres, robust (Huber) loss
// on loop closures, the first submap held fixed.
#include <array>
#include <vector>

#include "common/se2.h"

namespace cairn::agent {

struct PoseGraphOptions {
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

struct PoseGraphConstraint {
  enum class Kind { kIntraSubmap, kLoopClosure };
  int submap = 0;
  int node = 0;
  SE2 T_submap_node;
  Kind kind = Kind::kIntraSubmap;
  double score = 0.0;  ///< match score of a loop closure
};

class PoseGraph2D {
 public:
  explicit PoseGraph2D(const PoseGraphOptions& options = {});

  int add_submap(const SE2& T_global_submap);
  /// A node; consecutive nodes are tied by their local-SLAM relative pose `T_prev_node`.
  int add_node(const SE2& T_global_node, const SE2& T_local_node);
  void add_constraint(const PoseGraphConstraint& c);

  /// Runs Ceres (at most `max_num_iterations`, or the options' when <= 0); returns false when the
  /// solver reports an unusable solution (poses unchanged).
  bool optimize(int max_num_iterations = 0);

  const SE2& submap_pose(int i) const { return submaps_[size_t(i)]; }
  const SE2& node_pose(int i) const { return nodes_[size_t(i)]; }
  int num_submaps() const { return int(submaps_.size()); }
  int num_nodes() const { return int(nodes_.size()); }
  const std::vector<PoseGraphConstraint>& constraints() const { return constraints_; }
  int num_loop_closures() const { return num_loops_; }

 private:
  PoseGraphOptions options_;
  std::vector<SE2> submaps_;
  std::vector<SE2> nodes_;
  std::vector<SE2> local_nodes_;  ///< local-SLAM poses, for successive-node constraints
  std::vector<PoseGraphConstraint> constraints_;
  int num_loops_ = 0;
};

}  // namespace cairn::agent
