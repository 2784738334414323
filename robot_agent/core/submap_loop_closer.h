#pragma once
// SubmapLoopCloser: intra-robot loop closure for the local SLAM, scans against the robot's own
// older submaps (the base station's cross-robot closures between keyframes are base::KeyframeLoopCloser).
// After Cartographer's ConstraintBuilder2D + PoseGraph2D (Hess et al., ICRA 2016, Sec. V): every
// inserted scan becomes a node of a sparse pose graph over
// submaps and nodes; finished submaps get a branch-and-bound matcher (fast_correlative_scan_matcher.h);
// sampled nodes are searched against older finished submaps near their current estimate, matches
// are refined with Ceres and added as loop-closure constraints, and the graph is optimised
// periodically and at the end. New nodes and submaps enter the graph through the correction
// T_global_local of the newest submap, so the local SLAM itself never jumps.
// Search scheduling (what keeps it cheap): windows bounded by the drift measured by the
// optimisations since the last anchoring loop closure, tracking of a submap's latest closure, and a
// back-off for submaps whose searches keep failing (see the options).
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "common/se2.h"
#include "common/time.h"
#include "robot_agent/core/ceres_scan_matcher.h"
#include "robot_agent/core/correlative_scan_matcher.h"
#include "robot_agent/core/fast_correlative_scan_matcher.h"
#include "robot_agent/core/submap.h"
#include "robot_agent/core/submap_pose_graph.h"

namespace cairn::agent {

struct SubmapLoopCloserOptions {
  bool enabled = true;
  FastCorrelativeScanMatcherOptions fast;
  CeresScanMatcherOptions refine = [] {
    CeresScanMatcherOptions o;  // weak priors: the search result is only good to a cell
    o.translation_weight = o.rotation_weight = 0.1;
    o.max_num_iterations = 20;
    o.compute_covariance = false;  // loop closures are weighted by the score-surface covariance
    return o;
  }();
  SubmapPoseGraphOptions graph;
  /// The search window grows with the drift the node's estimate can have accumulated relative to
  /// the submap: window = min(max, base + per_node * gap), gap = the nodes since the submap was last
  /// touched.
  double linear_window_base_m = 0.3;
  double linear_window_per_node_m = 0.01;
  double linear_window_max_m = 4.0;
  double angular_window_base_rad = 3.0 * M_PI / 180.0;
  double angular_window_per_node_rad = 0.05 * M_PI / 180.0;
  double angular_window_max_rad = 20.0 * M_PI / 180.0;
  /// Anchored window (when smaller): once an optimisation has used a loop closure, the nodes after
  /// that "anchor" drift from the (now consistent) old submaps only by the local SLAM's drift over
  /// the distance travelled since: window = base + anchor_gap_factor * rate * travel, the rate
  /// being the drift the optimisations actually corrected per metre (the newest node's pose change
  /// over its travel since the previous anchor; the largest of the recent ones), at least the
  /// floors below. anchor_gap_factor = 0 disables the anchored window.
  double anchor_gap_factor = 2.0;
  double anchor_min_linear_rate = 0.05;                   ///< m of drift per m travelled
  double anchor_min_angular_rate_rad = 0.5 * M_PI / 180;  ///< rad of drift per m travelled
  int anchor_rate_memory = 4;  ///< optimisations over which the largest observed rate is kept
  /// Tracking: a node within this many nodes of the submap's latest accepted loop closure is
  /// searched around that closure's match moved by the local SLAM's relative motion since, with the
  /// anchored window for the travel since (the relative pose is already known; 0 disables).
  int tracking_max_gap_nodes = 16;
  /// Back-off: after k consecutive failed searches a submap skips min(k, this) sampled nodes (a
  /// submap near the robot but out of its view keeps failing; 0 disables).
  int max_failure_backoff = 3;
  double max_constraint_distance_m = 10.0;  ///< node to submap origin, current estimate
  double min_search_score = 0.5;            ///< of the branch-and-bound match (likelihood field, 0..1)
  double min_refined_score = 0.35;          ///< of the Ceres refinement (mean probability)
  int search_every_n_nodes = 4;             ///< sample nodes for the constraint search
  int min_node_separation = 0;              ///< a submap's last node must be at least this much older
  int optimize_every_n_nodes = 120;         ///< when new loop closures exist
  /// Periodic optimisations start from the previous solution and only need to be close (they seed
  /// the loop search); the final one (finish()) runs graph.max_num_iterations.
  int periodic_max_num_iterations = 10;
  /// Covariance-weighted loop closures: the match's score-surface covariance
  /// (correlative_scan_matcher.h score_surface_covariance) shapes the constraint's translation weight
  /// (submap_pose_graph.h anisotropic_sqrt_information), so a match along a featureless corridor only
  /// constrains the across-corridor position. (The Ceres refinement's Gauss-Newton covariance cannot
  /// be used: J^T J of the likelihood-field residuals vanishes across a wall at the optimum, where
  /// the field peaks, and is dominated by rasterisation ripples along it; submap_loop_closer_test.cpp.)
  bool covariance_weighting = true;
  ScoreSurfaceOptions score_surface;
  double covariance_min_weight_ratio = 0.05;  ///< along the worst direction, of the fixed weight
  /// The same for the local SLAM's constraints (intra-submap and successive nodes), shaped by the
  /// node's scan-to-submap match covariance: in a corridor the local SLAM's along-corridor motion is
  /// odometry only, so loop closures at the corridor's ends may correct it.
  bool local_covariance_weighting = true;
  double local_covariance_min_weight_ratio = 0.05;
  double search_voxel_m = 0.15;  ///< points used for the branch-and-bound search
  double refine_voxel_m = 0.08;  ///< points used for the Ceres refinement
};

struct SubmapLoopCloserStats {
  int searches = 0;
  int loop_closures = 0;
  int rejected_after_refinement = 0;
  int optimizations = 0;
  size_t matcher_bytes = 0;              ///< branch-and-bound grids built (only for submaps searched at least once)
  int64_t scored_candidates = 0;         ///< branch-and-bound work, all searches
  int64_t scored_candidates_failed = 0;  ///< ... of searches that found no match
  /// Covariance weighting: constraints whose weakest translation direction got < 1/2 of the weight.
  int anisotropic_loop_closures = 0;
  int anisotropic_local_nodes = 0;
};

class SubmapLoopCloser {
 public:
  explicit SubmapLoopCloser(const SubmapLoopCloserOptions& options = {});

  /// Adds the node of a scan inserted at `T_local_node` (`insertion` from ActiveSubmaps::insert,
  /// `submaps` after it; `covariance`: of the node's scan-to-submap match, local frame, when matched
  /// and local_covariance_weighting is on: score_surface_covariance in the upper-left block).
  /// Returns the node index.
  int add_node(const SE2& T_local_node, const std::vector<Eigen::Vector2f>& points_base,
               const SubmapInsertion& insertion, const ActiveSubmaps& submaps, const Covariance3* covariance = nullptr);
  /// Final optimisation (call at the end of a run).
  void finish();

  int num_nodes() const { return graph_.num_nodes(); }
  /// Current optimised pose of a node.
  const SE2& node_pose(int node) const { return graph_.node_pose(node); }
  const SE2& local_node_pose(int node) const { return local_nodes_[size_t(node)]; }
  /// Maps the local SLAM frame to the optimised frame (from the newest submap).
  SE2 T_global_local() const;
  const SubmapPoseGraph& graph() const { return graph_; }
  const SubmapLoopCloserStats& stats() const { return stats_; }

 private:
  struct SubmapEntry {
    SE2 T_local_submap;
    std::shared_ptr<const Submap> submap;                 ///< set when finished
    std::unique_ptr<FastCorrelativeScanMatcher> matcher;  ///< built at the first search reaching the submap
    int last_node = -1;
    int loop_node = -1;    ///< newest node with an accepted loop closure to this submap
    SE2 T_grid_loop_node;  ///< ... its matched pose in the submap grid's frame
    int failures = 0;      ///< consecutive failed searches
    int retry_node = 0;    ///< back-off: not searched again before this node
  };
  void search(int node, const std::vector<Eigen::Vector2f>& points, const std::vector<int>& own_submaps);
  bool try_submap(int node, SubmapEntry& entry, int submap_id, const std::vector<Eigen::Vector2f>& coarse,
                  const std::vector<Eigen::Vector2f>& fine);

  SubmapLoopCloserOptions options_;
  SubmapPoseGraph graph_;
  CeresScanMatcher refiner_;
  std::vector<SubmapEntry> submaps_;
  std::vector<SE2> local_nodes_;
  /// Optimises the graph; on success re-anchors and updates the observed drift rates.
  void optimize(int max_num_iterations);
  /// Search windows for a node against a submap (gap-based, bounded by the anchored window).
  void window(int node, const SubmapEntry& entry, double* linear_m, double* angular_rad) const;
  /// base + anchor_gap_factor * drift rate * travel between the nodes.
  void anchored_window(int anchor, int node, double* linear_m, double* angular_rad) const;

  std::vector<double> travel_m_;  ///< per node: distance travelled since the first node (local frame)
  std::vector<std::pair<double, double>> observed_rates_;  ///< recent (linear, angular) drift per metre
  int loops_since_optimize_ = 0;
  int last_loop_node_ = -1;  ///< newest node with an accepted loop closure
  int anchored_node_ = -1;   ///< last_loop_node_ as of the latest optimisation
  int nodes_since_optimize_ = 0;
  SubmapLoopCloserStats stats_;
};

}  // namespace cairn::agent
