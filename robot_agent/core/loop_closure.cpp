#include "robot_agent/core/loop_closure.h"

#include <algorithm>

#include "robot_agent/core/local_slam.h"

namespace cairn::agent {

LoopClosure::LoopClosure(const LoopClosureOptions& options)
    : options_(options), graph_(options.graph), refiner_(options.refine) {}

SE2 LoopClosure::T_global_local() const {
  if (submaps_.empty()) return SE2();
  const int last = int(submaps_.size()) - 1;
  return graph_.submap_pose(last) * submaps_.back().T_local_submap.inverse();
}

int LoopClosure::add_node(const SE2& T_local_node, const std::vector<Eigen::Vector2f>& points_base,
                          const SubmapInsertion& insertion, const ActiveSubmaps& submaps) {
  const SE2 correction = T_global_local();
  if (insertion.created) {
    const auto& s = *submaps.active().back();
    submaps_.push_back(SubmapEntry{s.T_local_submap, nullptr, nullptr, -1});
    graph_.add_submap(correction * s.T_local_submap);
  }
  const int node = graph_.add_node(correction * T_local_node, T_local_node);
  local_nodes_.push_back(T_local_node);
  for (int id : insertion.inserted_into) {
    SubmapEntry& e = submaps_[size_t(id)];
    e.last_node = node;
    graph_.add_constraint({id, node, e.T_local_submap.between(T_local_node), PoseGraphConstraint::Kind::kIntraSubmap, 1.0});
  }
  if (!options_.enabled) return node;
  if (insertion.finished) {
    SubmapEntry& e = submaps_[size_t(insertion.finished->id)];
    e.submap = insertion.finished;
    e.matcher = std::make_unique<FastCorrelativeScanMatcher>(insertion.finished->grid, options_.fast);
    stats_.matcher_bytes += e.matcher->memory_bytes();
  }
  if (node % std::max(1, options_.search_every_n_nodes) == 0) {
    search(node, points_base, insertion.inserted_into);
  }
  ++nodes_since_optimize_;
  if (loops_since_optimize_ > 0 && nodes_since_optimize_ >= options_.optimize_every_n_nodes) {
    if (graph_.optimize()) {
      ++stats_.optimizations;
      anchored_node_ = last_loop_node_;
    }
    loops_since_optimize_ = 0;
    nodes_since_optimize_ = 0;
  }
  return node;
}

void LoopClosure::search(int node, const std::vector<Eigen::Vector2f>& points_base, const std::vector<int>& own) {
  const SE2& T_global_node = graph_.node_pose(node);
  std::vector<Eigen::Vector2f> coarse, fine;
  for (int id = 0; id < int(submaps_.size()); ++id) {
    SubmapEntry& e = submaps_[size_t(id)];
    if (!e.matcher || std::find(own.begin(), own.end(), id) != own.end()) continue;
    if (e.last_node > node - options_.min_node_separation) continue;
    const SE2 T_submap_node = graph_.submap_pose(id).between(T_global_node);
    if (T_submap_node.translation().norm() > options_.max_constraint_distance_m) continue;
    if (coarse.empty()) {
      coarse = voxel_filter_2d(points_base, options_.search_voxel_m);
      fine = voxel_filter_2d(points_base, options_.refine_voxel_m);
    }
    if (try_submap(node, e, id, coarse, fine)) {
      last_loop_node_ = node;
      ++stats_.loop_closures;
      ++loops_since_optimize_;
    }
  }
}

bool LoopClosure::try_submap(int node, SubmapEntry& e, int id, const std::vector<Eigen::Vector2f>& points,
                             const std::vector<Eigen::Vector2f>& fine) {
  ++stats_.searches;
  // The initial guess in the submap grid's (local) frame, from the current optimised poses.
  const SE2 T_submap_node = graph_.submap_pose(id).between(graph_.node_pose(node));
  const SE2 initial = e.T_local_submap * T_submap_node;
  const LoopClosureOptions& o = options_;
  double gap = double(node - e.last_node);
  if (o.anchor_gap_factor > 0.0 && anchored_node_ >= 0) {
    gap = std::min(gap, o.anchor_gap_factor * double(node - anchored_node_));
  }
  const double linear_m = std::min(o.linear_window_max_m, o.linear_window_base_m + o.linear_window_per_node_m * gap);
  const double angular_rad =
      std::min(o.angular_window_max_rad, o.angular_window_base_rad + o.angular_window_per_node_rad * gap);
  int scored = 0;
  const auto found = e.matcher->match(initial, points, linear_m, angular_rad, o.min_search_score, &scored);
  stats_.scored_candidates += scored;
  if (!found) {
    stats_.scored_candidates_failed += scored;
    return false;
  }
  const CeresMatch refined = refiner_.match(found->pose, fine, e.submap->grid);
  if (!refined.converged || refined.score < options_.min_refined_score) {
    ++stats_.rejected_after_refinement;
    return false;
  }
  graph_.add_constraint({id, node, e.T_local_submap.between(refined.pose), PoseGraphConstraint::Kind::kLoopClosure,
                         refined.score});
  return true;
}

void LoopClosure::finish() {
  if (!options_.enabled || graph_.num_loop_closures() == 0) return;
  if (graph_.optimize()) {
    ++stats_.optimizations;
    anchored_node_ = last_loop_node_;
  }
  loops_since_optimize_ = 0;
  nodes_since_optimize_ = 0;
}

}  // namespace cairn::agent
