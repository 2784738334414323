#include "robot_agent/core/submap_loop_closer.h"

#include <Eigen/Eigenvalues>
#include <algorithm>

#include "common/laser_scan.h"

namespace cairn::agent {
namespace {

// Weakest over strongest translation weight of a square-root information.
double weight_ratio(const Eigen::Matrix3d& L) {
  const Eigen::Vector2d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(L.topLeftCorner<2, 2>()).eigenvalues();
  return ev(1) > 0.0 ? ev(0) / ev(1) : 1.0;
}

}  // namespace

SubmapLoopCloser::SubmapLoopCloser(const SubmapLoopCloserOptions& options)
    : options_(options), graph_(options.graph), refiner_(options.refine) {}

SE2 SubmapLoopCloser::T_global_local() const {
  if (submaps_.empty()) return SE2();
  const int last = int(submaps_.size()) - 1;
  return graph_.submap_pose(last) * submaps_.back().T_local_submap.inverse();
}

int SubmapLoopCloser::add_node(const SE2& T_local_node, const std::vector<Eigen::Vector2f>& points_base,
                               const SubmapInsertion& insertion, const ActiveSubmaps& submaps,
                               const Covariance3* covariance) {
  const SE2 correction = T_global_local();
  if (insertion.created) {
    const auto& s = *submaps.active().back();
    submaps_.push_back(SubmapEntry{s.T_local_submap, nullptr, nullptr, -1});
    graph_.add_submap(correction * s.T_local_submap);
  }
  const SubmapLoopCloserOptions& o = options_;
  const bool shaped = o.local_covariance_weighting && covariance != nullptr;
  Eigen::Matrix3d successive;
  if (shaped && !local_nodes_.empty()) {
    successive =
        anisotropic_sqrt_information(*covariance, -local_nodes_.back().yaw(), o.graph.successive_translation_weight,
                                     o.graph.successive_rotation_weight, o.local_covariance_min_weight_ratio);
    if (weight_ratio(successive) < 0.5) ++stats_.anisotropic_local_nodes;
  }
  const int node =
      graph_.add_node(correction * T_local_node, T_local_node, shaped && !local_nodes_.empty() ? &successive : nullptr);
  travel_m_.push_back(local_nodes_.empty()
                          ? 0.0
                          : travel_m_.back() + (T_local_node.translation() - local_nodes_.back().translation()).norm());
  local_nodes_.push_back(T_local_node);
  for (int id : insertion.inserted_into) {
    SubmapEntry& e = submaps_[size_t(id)];
    e.last_node = node;
    SubmapPoseGraphConstraint c{id, node, e.T_local_submap.between(T_local_node),
                                SubmapPoseGraphConstraint::Kind::kIntraSubmap, 1.0};
    if (shaped) {
      c.has_sqrt_information = true;
      c.sqrt_information =
          anisotropic_sqrt_information(*covariance, -e.T_local_submap.yaw(), o.graph.intra_translation_weight,
                                       o.graph.intra_rotation_weight, o.local_covariance_min_weight_ratio);
    }
    graph_.add_constraint(c);
  }
  if (!options_.enabled) return node;
  if (insertion.finished) {
    SubmapEntry& e = submaps_[size_t(insertion.finished->id)];
    e.submap = insertion.finished;  // its matcher is built at the first search that reaches it
  }
  if (node % std::max(1, options_.search_every_n_nodes) == 0) {
    search(node, points_base, insertion.inserted_into);
  }
  ++nodes_since_optimize_;
  if (loops_since_optimize_ > 0 && nodes_since_optimize_ >= options_.optimize_every_n_nodes) {
    optimize(options_.periodic_max_num_iterations);
  }
  return node;
}

void SubmapLoopCloser::optimize(int max_num_iterations) {
  const int newest = graph_.num_nodes() - 1;
  const SE2 before = newest >= 0 ? graph_.node_pose(newest) : SE2();
  loops_since_optimize_ = 0;
  nodes_since_optimize_ = 0;
  if (!graph_.optimize(max_num_iterations)) return;
  ++stats_.optimizations;
  if (newest < 0) return;
  // The newest node's correction is the drift accumulated since the previous anchor (or the start).
  const SE2 after = graph_.node_pose(newest);
  const double travel_m = travel_m_[size_t(newest)] - (anchored_node_ >= 0 ? travel_m_[size_t(anchored_node_)] : 0.0);
  if (travel_m > 1.0) {
    observed_rates_.emplace_back((after.translation() - before.translation()).norm() / travel_m,
                                 std::abs(normalize_angle(after.yaw() - before.yaw())) / travel_m);
    const size_t keep = size_t(std::max(1, options_.anchor_rate_memory));
    if (observed_rates_.size() > keep) observed_rates_.erase(observed_rates_.begin());
  }
  anchored_node_ = last_loop_node_;
}

void SubmapLoopCloser::anchored_window(int anchor, int node, double* linear_m, double* angular_rad) const {
  const SubmapLoopCloserOptions& o = options_;
  double linear_rate = o.anchor_min_linear_rate, angular_rate = o.anchor_min_angular_rate_rad;
  for (const auto& [l, a] : observed_rates_) {
    linear_rate = std::max(linear_rate, l);
    angular_rate = std::max(angular_rate, a);
  }
  const double travel_m = travel_m_[size_t(node)] - travel_m_[size_t(anchor)];
  *linear_m = o.linear_window_base_m + o.anchor_gap_factor * linear_rate * travel_m;
  *angular_rad = o.angular_window_base_rad + o.anchor_gap_factor * angular_rate * travel_m;
}

void SubmapLoopCloser::window(int node, const SubmapEntry& e, double* linear_m, double* angular_rad) const {
  const SubmapLoopCloserOptions& o = options_;
  const double gap = double(node - e.last_node);
  *linear_m = std::min(o.linear_window_max_m, o.linear_window_base_m + o.linear_window_per_node_m * gap);
  *angular_rad = std::min(o.angular_window_max_rad, o.angular_window_base_rad + o.angular_window_per_node_rad * gap);
  if (o.anchor_gap_factor <= 0.0 || anchored_node_ < 0) return;
  double l = 0.0, a = 0.0;
  anchored_window(anchored_node_, node, &l, &a);
  *linear_m = std::min(*linear_m, l);
  *angular_rad = std::min(*angular_rad, a);
}

void SubmapLoopCloser::search(int node, const std::vector<Eigen::Vector2f>& points_base, const std::vector<int>& own) {
  const SE2& T_global_node = graph_.node_pose(node);
  std::vector<Eigen::Vector2f> coarse, fine;
  for (int id = 0; id < int(submaps_.size()); ++id) {
    SubmapEntry& e = submaps_[size_t(id)];
    if (!e.submap || std::find(own.begin(), own.end(), id) != own.end()) continue;
    if (e.last_node > node - options_.min_node_separation) continue;
    if (node < e.retry_node) continue;
    const SE2 T_submap_node = graph_.submap_pose(id).between(T_global_node);
    if (T_submap_node.translation().norm() > options_.max_constraint_distance_m) continue;
    if (coarse.empty()) {
      coarse = voxel_filter_2d(points_base, options_.search_voxel_m);
      fine = voxel_filter_2d(points_base, options_.refine_voxel_m);
    }
    if (!e.matcher) {
      // Lazily: a finished submap no later node comes near never needs its precomputation grids
      // (CPU and, mostly, fresh memory the kernel has to zero).
      e.matcher = std::make_unique<FastCorrelativeScanMatcher>(e.submap->grid, options_.fast);
      stats_.matcher_bytes += e.matcher->memory_bytes();
    }
    if (try_submap(node, e, id, coarse, fine)) {
      last_loop_node_ = node;
      ++stats_.loop_closures;
      ++loops_since_optimize_;
    }
  }
}

bool SubmapLoopCloser::try_submap(int node, SubmapEntry& e, int id, const std::vector<Eigen::Vector2f>& points,
                                  const std::vector<Eigen::Vector2f>& fine) {
  ++stats_.searches;
  // The initial guess in the submap grid's (local) frame, from the current optimised poses.
  const SE2 T_submap_node = graph_.submap_pose(id).between(graph_.node_pose(node));
  SE2 initial = e.T_local_submap * T_submap_node;
  const SubmapLoopCloserOptions& o = options_;
  double linear_m = 0.0, angular_rad = 0.0;
  window(node, e, &linear_m, &angular_rad);
  if (o.tracking_max_gap_nodes > 0 && e.loop_node >= 0 && node - e.loop_node <= o.tracking_max_gap_nodes) {
    // Tracking: the latest closure to this submap moved by the local SLAM's motion since.
    double l = 0.0, a = 0.0;
    anchored_window(e.loop_node, node, &l, &a);
    if (l <= linear_m && a <= angular_rad) {
      initial = e.T_grid_loop_node * local_nodes_[size_t(e.loop_node)].between(local_nodes_[size_t(node)]);
      linear_m = l;
      angular_rad = a;
    }
  }
  int scored = 0;
  const size_t matcher_bytes = e.matcher->memory_bytes();
  const auto found = e.matcher->match(initial, points, linear_m, angular_rad, o.min_search_score, &scored);
  stats_.matcher_bytes += e.matcher->memory_bytes() - matcher_bytes;  // levels built by this search
  stats_.scored_candidates += scored;
  const auto fail = [&] {
    ++e.failures;
    e.retry_node = node + std::max(1, o.search_every_n_nodes) * std::min(e.failures, o.max_failure_backoff) + 1;
    return false;
  };
  if (!found) {
    stats_.scored_candidates_failed += scored;
    return fail();
  }
  const CeresMatch refined = refiner_.match(found->pose, fine, e.submap->grid);
  if (!refined.converged || refined.score < options_.min_refined_score) {
    ++stats_.rejected_after_refinement;
    return fail();
  }
  e.failures = 0;
  SubmapPoseGraphConstraint c{id, node, e.T_local_submap.between(refined.pose),
                              SubmapPoseGraphConstraint::Kind::kLoopClosure, refined.score};
  if (o.covariance_weighting) {
    // The covariance is over the pose in the grid (local) frame; the residual is in the submap's.
    c.has_sqrt_information = true;
    Covariance3 cov = Covariance3::Identity();
    cov.topLeftCorner<2, 2>() = score_surface_covariance(e.submap->grid, refined.pose, points, o.score_surface);
    c.sqrt_information = anisotropic_sqrt_information(cov, -e.T_local_submap.yaw(), o.graph.loop_translation_weight,
                                                      o.graph.loop_rotation_weight, o.covariance_min_weight_ratio);
    if (weight_ratio(c.sqrt_information) < 0.5) ++stats_.anisotropic_loop_closures;
  }
  graph_.add_constraint(c);
  e.loop_node = node;
  e.T_grid_loop_node = refined.pose;
  return true;
}

void SubmapLoopCloser::finish() {
  if (!options_.enabled || graph_.num_loop_closures() == 0) return;
  optimize(options_.graph.max_num_iterations);
}

}  // namespace cairn::agent
