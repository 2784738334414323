// MultiRobotMapper: the pose graph of the linked robots and its incremental update (see
// multi_robot_mapper.h). New keyframes are chained onto the live Ceres problem and solved in a
// window; loop, landmark and object edges trigger full warm-started refinements; a new link
// re-initialises the whole graph from LAGO.
#include <algorithm>
#include <climits>
#include <cmath>

#include "base_station/core/lago_initializer.h"
#include "base_station/core/multi_robot_mapper.h"
#include "common/robot_markers.h"

namespace cairn::base {
namespace {

/// The robot's first keyframe not in the graph yet (the end of its range when all are). Keyframes
/// enter the graph in seq order (one arriving before a placed successor forces a rebuild), so this
/// walks back over the new ones only: O(new keyframes), not O(trajectory).
KeyframeMap::const_iterator first_unplaced(const MapperData& data, const KeyframePoseGraph& graph, RobotId robot) {
  const RobotKeyframes range = data.robot_keyframes(robot);
  auto it = range.end();
  while (it != range.begin() && !graph.has_node(std::prev(it)->first)) --it;
  return it;
}

/// Appends the keyframes of `robot` from `window` before `from` to the end of its trajectory
/// (nothing when `from` is not one of its keyframes).
void append_window(const KeyframeMap& keyframes, RobotId robot, KeyframeMap::const_iterator from, int window,
                   std::vector<KeyframeId>* out) {
  if (from == keyframes.end() || from->first.robot != robot) return;
  for (int k = 0; k < window && from != keyframes.begin() && std::prev(from)->first.robot == robot; ++k) --from;
  for (; from != keyframes.end() && from->first.robot == robot; ++from) out->push_back(from->first);
}

}  // namespace

void MultiRobotMapper::update_graph(bool full_resolve, OptimizeResult* result) {
  refresh_object_constraints();  // multi_robot_mapper_objects.cpp; may ask for a rebuild
  rebuild_graph_if_needed();
  remeasure_changed_chains();
  // New keyframes of each linked robot (O(robots + new keyframes), not O(keyframes)).
  const int window = std::max(0, options_.incremental_window_keyframes);
  std::vector<KeyframeId> active;
  for (RobotId robot : data_.keyframe_robots()) {
    if (!linked(robot)) continue;
    append_window(data_.keyframes, robot, first_unplaced(data_, graph_, robot), window, &active);
    add_robot_chain(robot, result);
  }
  const size_t edges_before = graph_.edges().size();
  const size_t landmark_edges_before = graph_.landmark_edges().size();
  add_loop_edges();
  add_sighting_edges();
  add_object_edges();  // multi_robot_mapper_objects.cpp
  if (graph_.edges().size() > edges_before || graph_.landmark_edges().size() > landmark_edges_before) {
    // A new loop moves the optimum of the whole graph: solving only a window around it first
    // bends the held-constant rest into the window (metres after a fresh inter-robot link) and
    // leaves the full solves a worse start, so loops go to full warm-started solves (at most every
    // refine_every_updates while keyframes arrive; in between only the new keyframes' windows).
    refine_pending_ = true;
  }
  if (!options_.windowed_updates) refine_pending_ = true;  // every update: the whole graph
  if (updates_since_refine_ < INT_MAX) ++updates_since_refine_;
  solve(full_resolve, std::move(active), result);
}

void MultiRobotMapper::rebuild_graph_if_needed() {
  if (!options_.incremental_graph) rebuild_graph_ = true;  // mapper_options.h: why
  if (!rebuild_graph_) return;
  graph_ = KeyframePoseGraph(options_.graph);
  loop_in_graph_.assign(data_.loops.size(), false);
  sighting_done_.assign(data_.sightings.size(), false);
  object_edges_in_graph_.clear();
  rebuild_graph_ = false;
}

void MultiRobotMapper::remeasure_changed_chains() {
  // Chains re-measured by their agents' loop closing: edge measurements replaced in place (the
  // live problem is kept), then a full warm-started solve. O(edges), no rebuild.
  if (chains_changed_.empty()) return;
  const std::vector<PoseGraphEdge>& edges = graph_.edges();
  for (size_t i = 0; i < edges.size(); ++i) {
    const PoseGraphEdge& e = edges[i];
    if (e.kind != EdgeKind::kOdometry || e.from.robot != e.to.robot || !chains_changed_.count(e.from.robot)) continue;
    bool gap = false;
    const PoseGraphEdge chain = chain_edge(data_, data_.keyframe(e.from), data_.keyframe(e.to), options_, &gap);
    graph_.set_edge_measurement(i, chain.T_from_to, chain.information);
  }
  refine_pending_ = true;
  chains_changed_.clear();
}

void MultiRobotMapper::add_robot_chain(RobotId robot, OptimizeResult* result) {
  const SE2 T_global_local = data_.correction(robot);
  const Keyframe* prev = nullptr;
  SE2 prev_initial;
  bool placed_new = false;
  const RobotKeyframes range = data_.robot_keyframes(robot);
  auto it = first_unplaced(data_, graph_, robot);
  if (it != range.begin()) {
    prev = &std::prev(it)->second;
    prev_initial = *graph_.estimate(prev->id);
  }
  for (; it != range.end(); ++it) {
    const Keyframe& kf = it->second;
    if (graph_.has_node(kf.id)) {
      prev = &kf;
      prev_initial = *graph_.estimate(kf.id);
      continue;
    }
    bool gap = false;
    const PoseGraphEdge edge =
        prev ? chain_edge(data_, *prev, kf, options_, &gap) : PoseGraphEdge{kf.id, kf.id, {}, {}, EdgeKind::kOdometry};
    result->gap_edges += gap;
    auto opt = data_.optimized.find(kf.id);
    const SE2 initial = opt != data_.optimized.end() ? opt->second
                        : prev                       ? prev_initial * edge.T_from_to
                                                     : T_global_local * kf.T_local_base;
    placed_new |= graph_.add_node(kf.id, initial);
    if (prev) {
      graph_.add_edge(edge);
    } else if (data_.hints.count(robot) || robot == data_.anchor) {
      graph_.set_prior(
          PosePrior{kf.id, data_.starts.at(robot) * kf.T_local_base,
                    diag_information(options_.start_prior_sigma_xy_m, options_.start_prior_sigma_yaw_rad)});
    }
    prev = &kf;
    prev_initial = initial;
  }
  // Only new nodes can lack landmark edges (a rebuilt graph makes every node new).
  if (placed_new) add_landmark_edges(robot);
}

void MultiRobotMapper::add_loop_edges() {
  loop_in_graph_.resize(data_.loops.size(), false);
  for (size_t i = 0; i < data_.loops.size(); ++i) {
    const LoopClosure& c = data_.loops[i];
    if (loop_in_graph_[i] || !graph_.has_node(c.a) || !graph_.has_node(c.b)) continue;
    loop_in_graph_[i] = graph_.add_edge(loop_edge(c));
  }
}

void MultiRobotMapper::add_landmark_edges(RobotId robot) {
  const LandmarkOptions& o = options_.landmarks;
  if (!o.enabled) return;
  for (const auto& [id, kf] : data_.robot_keyframes(robot)) {
    if (kf.landmarks.empty() || !graph_.has_node(id) || graph_.has_landmark_edges_from(id)) continue;
    for (const LandmarkObservation& l : kf.landmarks) {
      if (robot_of_marker(l.id) || !validate_landmark_observation(l).empty() || l.range_m < o.min_range_m) continue;
      graph_.add_landmark_edge(LandmarkEdge{id, l.id, l.range_m, l.bearing_rad, o.sigma_scale * l.sigma_range_m,
                                            o.sigma_scale * l.sigma_bearing_rad});
    }
  }
}

void MultiRobotMapper::add_sighting_edges() {
  const LandmarkOptions& o = options_.landmarks;
  if (!o.enabled) return;
  sighting_done_.resize(data_.sightings.size(), false);
  for (size_t i = 0; i < data_.sightings.size(); ++i) {
    const Sighting& s = data_.sightings[i];
    if (sighting_done_[i] || !graph_.has_node(s.observer) || !linked(s.seen)) continue;
    const StampNs t = s.observation.stamp_ns;
    const std::optional<SeenPosition> seen = position_at(data_, s.seen, t, o.sighting_min_offset_m);
    if (!seen) {
      sighting_done_[i] = has_keyframe_after(data_, s.seen, t);  // decided: the robot stood still
      continue;
    }
    if (!graph_.has_node(seen->keyframe)) continue;
    const SightingNodeId node{int32_t(i)};
    const LandmarkObservation& z = s.observation;
    const double k = o.sighting_sigma_scale, r = seen->point_m.norm();
    const double sigma_m = k * o.sighting_interpolation_sigma_m;
    graph_.add_landmark_edge(
        LandmarkEdge{s.observer, node, z.range_m, z.bearing_rad, k * z.sigma_range_m, k * z.sigma_bearing_rad});
    graph_.add_landmark_edge(
        LandmarkEdge{seen->keyframe, node, r, std::atan2(seen->point_m.y(), seen->point_m.x()), sigma_m, sigma_m / r});
    sighting_done_[i] = true;
  }
}

void MultiRobotMapper::solve(bool full_resolve, std::vector<KeyframeId> active, OptimizeResult* result) {
  PoseGraphSolveOptions solve = options_.solve;
  if (full_resolve) {  // a new link: the whole graph from a LAGO initialisation
    updates_since_refine_ = 0;
    if (const auto init = lago_initialize(graph_)) graph_.set_estimates(*init);
    result->full_resolve = true;
    refine_pending_ = false;
    result->full_solve = true;
    result->solve = graph_.solve(solve);
    return;
  }
  solve.max_iterations = std::min(solve.max_iterations, options_.incremental_max_iterations);
  std::sort(active.begin(), active.end());
  active.erase(std::unique(active.begin(), active.end()), active.end());
  // Full refinement now: when idle, or at most every refine_interval updates (mapper_options.h).
  const int per_update = options_.refine_keyframes_per_update;
  const int refine_interval =
      std::max({1, options_.refine_every_updates, per_update > 0 ? int(graph_.num_nodes()) / per_update : 0});
  const bool refine_now =
      refine_pending_ && (active.empty() || !options_.windowed_updates || updates_since_refine_ >= refine_interval);
  if (!active.empty() && !refine_now) {  // the new keyframes' window (exact for odometry alone)
    PoseGraphSolveOptions local = solve;
    local.active_nodes = active;
    result->solve = graph_.solve(local);
    for (KeyframeId id : active) data_.optimized[id] = *graph_.estimate(id);
    map_.moved(active);
  } else if (!refine_now) {
    result->solve.converged = true;
    result->solve.reason = "nothing new";
    result->solve.initial_cost = result->solve.final_cost = graph_.evaluate_cost();  // not 0: the graph's cost
  }
  if (refine_now) {
    updates_since_refine_ = 0;
    solve.max_time_s = options_.refine_max_time_s;
    result->solve = graph_.solve(solve);
    result->full_solve = true;
    refine_pending_ = !result->solve.converged;
    for (const auto& [id, pose] : graph_.estimates()) data_.optimized[id] = pose;
    map_.all_moved();
  }
}

}  // namespace cairn::base
