#pragma once
// Intra-robot loop closure for the local SLAM (Cartographer's ConstraintBuilder2D + PoseGraph2D;
// Hess et al., ICRA 2016, Sec. V): every inserted scan becomes a node of a sparse pose graph over
// submaps and nodes; finished submaps get a branch-and-bound matcher (fast_correlative_scan_matcher.h);
// sampled nodes are searched against older finished submaps near their current estimate, matches
// are refined with Ceres and added as loop-closure constraints, and the graph is optimised
// periodically and at the end. New nodes and submaps enter the graph through the correction
// T_global_local of the newest submap, so the local SLAM itself never jumps.
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "common/se2.h"
#include "common/time.h"
#include "robot_agent/core/ceres_scan_matcher.h"
#include "robot_agent/core/fast_correlative_scan_matcher.h"
#include "robot_agent/core/pose_graph_2d.h"
#include "robot_agent/core/submap.h"

namespace cairn::agent {

struct LoopClosureOptions {
  bool enabled = true;
  FastCorrelativeScanMatcherOptions fast;
  CeresScanMatcherOptions refine = [] {
    CeresScanMatcherOptions o;  // weak priors: the search result is only good to a cell
    o.translation_weight = o.rotation_weight = 0.1;
    o.max_num_iterations = 20;
    return o;
  }();
  PoseGraphOptions graph;
  /// The search window grows with the drift the node's estimate can have accumulated relative to
  /// the submap: window = min(max, base + per_node * gap), gap = the nodes since the submap was last
  /// touched or, when fewer, anchor_gap_factor times the nodes since the newest node whose loop
  /// closure the graph has been optimised with (which anchored the trajectory to the old submaps;
  /// the factor allows for the residual error of that correction; 0 disables the anchor).
  double linear_window_base_m = 0.3;
  double linear_window_per_node_m = 0.01;
  double linear_window_max_m = 4.0;
  double angular_window_base_rad = 3.0 * M_PI / 180.0;
  double angular_window_per_node_rad = 0.05 * M_PI / 180.0;
  double angular_window_max_rad = 20.0 * M_PI / 180.0;
  double anchor_gap_factor = 0.0;
  double max_constraint_distance_m = 10.0;  ///< node to submap origin, current estimate
  double min_search_score = 0.5;           ///< of the branch-and-bound match (likelihood field, 0..1)
  double min_refined_score = 0.35;        ///< of the Ceres refinement (mean probability)
  int search_every_n_nodes = 4;            ///< sample nodes for the constraint search
  int min_node_separation = 0;             ///< a submap's last node must be at least this much older
  int optimize_every_n_nodes = 120;        ///< when new loop closures exist
  double search_voxel_m = 0.15;            ///< points used for the branch-and-bound search
  double refine_voxel_m = 0.08;            ///< points used for the Ceres refinement
};

struct LoopClosureStats {
  int searches = 0;
  int loop_closures = 0;
  int rejected_after_refinement = 0;
  int optimizations = 0;
  size_t matcher_bytes = 0;
  int64_t scored_candidates = 0;         ///< branch-and-bound work, all searches
  int64_t scored_candidates_failed = 0;  ///< ... of searches that found no match
};

class LoopClosure {
 public:
  explicit LoopClosure(const LoopClosureOptions& options = {});

  /// Adds the node of a scan inserted at `T_local_node` (`insertion` from ActiveSubmaps::insert,
  /// `submaps` after it). Returns the node index.
  int add_node(const SE2& T_local_node, const std::vector<Eigen::Vector2f>& points_base,
               const SubmapInsertion& insertion, const ActiveSubmaps& submaps);
  /// Final optimisation (call at the end of a run).
  void finish();

  int num_nodes() const { return graph_.num_nodes(); }
  /// Current optimised pose of a node.
  const SE2& node_pose(int node) const { return graph_.node_pose(node); }
  const SE2& local_node_pose(int node) const { return local_nodes_[size_t(node)]; }
  /// Maps the local SLAM frame to the optimised frame (from the newest submap).
  SE2 T_global_local() const;
  const PoseGraph2D& graph() const { return graph_; }
  const LoopClosureStats& stats() const { return stats_; }

 private:
  struct SubmapEntry {
    SE2 T_local_submap;
    std::shared_ptr<const Submap> submap;             ///< set when finished
    std::unique_ptr<FastCorrelativeScanMatcher> matcher;
    int last_node = -1;
  };
  void search(int node, const std::vector<Eigen::Vector2f>& points, const std::vector<int>& own_submaps);
  bool try_submap(int node, SubmapEntry& entry, int submap_id, const std::vector<Eigen::Vector2f>& coarse,
                  const std::vector<Eigen::Vector2f>& fine);

  LoopClosureOptions options_;
  PoseGraph2D graph_;
  CeresScanMatcher refiner_;
  std::vector<SubmapEntry> submaps_;
  std::vector<SE2> local_nodes_;
  int loops_since_optimize_ = 0;
  int last_loop_node_ = -1;      ///< newest node with an accepted loop closure
  int anchored_node_ = -1;       ///< last_loop_node_ as of the latest optimisation
  int nodes_since_optimize_ = 0;
  LoopClosureStats stats_;
};

}  // namespace cairn::agent
