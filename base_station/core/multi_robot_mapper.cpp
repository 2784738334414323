#include "base_station/core/multi_robot_mapper.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <climits>
#include <cmath>
#include <set>

#include "base_station/core/lago_initializer.h"
#include "common/laser_scan.h"

namespace cairn::base {
namespace {

bool finite(const SE2& T) { return T.vector().allFinite(); }

Eigen::Matrix3d diag_information(double sigma_xy_m, double sigma_yaw_rad) {
  return Eigen::Vector3d(1.0 / (sigma_xy_m * sigma_xy_m), 1.0 / (sigma_xy_m * sigma_xy_m),
                         1.0 / (sigma_yaw_rad * sigma_yaw_rad))
      .asDiagonal();
}

/// Information of a measured edge; nullopt when the covariance is not positive definite.
std::optional<Eigen::Matrix3d> information_of(const Covariance3& covariance) {
  const Eigen::Matrix3d sym = 0.5 * (covariance + covariance.transpose());
  Eigen::LLT<Eigen::Matrix3d> llt(sym);
  if (llt.info() != Eigen::Success) return std::nullopt;
  const Eigen::Matrix3d info = llt.solve(Eigen::Matrix3d::Identity());
  if (!info.allFinite()) return std::nullopt;
  return info;
}

/// Why a keyframe cannot be stored, or empty when it is valid.
std::string validate(const Keyframe& kf) {
  if (!kf.id.robot.valid()) return "invalid robot id " + std::to_string(kf.id.robot.value);
  if (kf.id.seq < 0) return "invalid keyframe seq " + std::to_string(kf.id.seq);
  if (!finite(kf.T_local_base)) return "non-finite pose T_local_base";
  if (!kf.covariance.allFinite()) return "non-finite pose covariance";
  if (kf.id.seq > 0 && !finite(kf.T_prev_this)) return "non-finite odometry edge T_prev_this";
  if (kf.id.seq > 0 && !kf.edge_covariance.allFinite()) return "non-finite edge covariance";
  if (!std::isfinite(kf.scan.angle_min_rad) || !std::isfinite(kf.scan.angle_increment_rad)) {
    return "non-finite scan geometry";
  }
  return {};
}

using KeyframeMap = std::map<KeyframeId, Keyframe>;

/// The robot's first keyframe not in the graph yet (the end of its range when all are). Keyframes
/// enter the graph in seq order (one arriving before a placed successor forces a rebuild), so this
/// walks back over the new ones only: O(new keyframes), not O(trajectory).
KeyframeMap::const_iterator first_unplaced(const KeyframeMap& keyframes, const PoseGraph2d& graph, RobotId robot) {
  const auto begin = keyframes.lower_bound(KeyframeId{robot, 0});
  auto it = keyframes.upper_bound(KeyframeId{robot, INT32_MAX});
  while (it != begin && !graph.has_node(std::prev(it)->first)) --it;
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

GlobalMapRenderOptions map_render_options(const MapperOptions& options) {
  GlobalMapRenderOptions o = options.map_render;
  o.no_return_clear_range_m = options.no_return_clear_range_m;
  return o;
}

}  // namespace

const char* to_string(AddStatus status) {
  switch (status) {
    case AddStatus::kAccepted:
      return "accepted";
    case AddStatus::kPending:
      return "pending";
    case AddStatus::kDuplicate:
      return "duplicate";
    case AddStatus::kRejected:
      return "rejected";
  }
  return "unknown";
}

MultiRobotMapper::MultiRobotMapper(const MapperOptions& options)
    : options_(options),
      loop_closer_(options.loop_closer),
      graph_(options.graph),
      map_(options.grid, map_render_options(options)) {}

void MultiRobotMapper::set_robot_start(RobotId robot, const SE2& T_global_local) {
  if (!robot.valid() || !finite(T_global_local)) return;
  starts_[robot] = T_global_local;
  hints_[robot] = T_global_local;
  rebuild_graph_ = true;
  // Earlier solutions of this robot were relative to another start: re-initialise from the new one.
  for (auto it = optimized_.begin(); it != optimized_.end();) {
    it = it->first.robot == robot ? optimized_.erase(it) : std::next(it);
  }
  map_all_moved_ = true;
  note_poses_changed();
  ++version_;
}

AddResult MultiRobotMapper::add_keyframe(const Keyframe& kf) {
  const std::string invalid = validate(kf);
  if (!invalid.empty()) return {AddStatus::kRejected, to_string(kf.id) + ": " + invalid};
  if (keyframes_.count(kf.id)) return {AddStatus::kDuplicate, to_string(kf.id) + " already stored"};
  keyframes_.emplace(kf.id, kf);
  detect_queue_.push_back(kf.id);
  ++version_;
  note_landmarks(kf);  // multi_robot_mapper_landmarks.cpp
  if (graph_.has_node(kf.id)) rebuild_graph_ = true;
  auto next = keyframes_.upper_bound(kf.id);
  if (next != keyframes_.end() && next->first.robot == kf.id.robot && graph_.has_node(next->first)) {
    rebuild_graph_ = true;  // arrived after its successor: the gap edge must go
  }
  if (!anchor_committed_ && hints_.empty() && (!anchor_ || kf.id.robot < *anchor_)) {
    if (anchor_) starts_.erase(*anchor_);
    map_all_moved_ = true;
    anchor_ = kf.id.robot;
    starts_[kf.id.robot] = SE2();
  }
  if (!linked(kf.id.robot)) {
    return {AddStatus::kPending,
            to_string(kf.id.robot) +
                " not linked to the others yet (waiting for verified inter-robot loop closures): kept, not placed"};
  }
  map_moved_.push_back(kf.id);
  note_poses_changed();
  AddResult result{AddStatus::kAccepted, {}};
  if (kf.id.seq > 0 && !keyframes_.count(KeyframeId{kf.id.robot, kf.id.seq - 1})) {
    result.reason =
        "predecessor seq " + std::to_string(kf.id.seq - 1) + " missing: linked by local pose until it arrives";
  } else if (kf.id.seq > 0 && !information_of(kf.edge_covariance)) {
    result.reason = "edge covariance not positive definite: gap uncertainty used";
  }
  return result;
}

AddResult MultiRobotMapper::add_keyframe_poses(const KeyframePoses& update) {
  const std::string who = to_string(update.robot) + " keyframe poses";
  if (!update.robot.valid())
    return {AddStatus::kRejected, "keyframe poses: invalid robot id " + std::to_string(update.robot.value)};
  for (size_t i = 0; i < update.poses.size(); ++i) {
    const KeyframePose& p = update.poses[i];
    if (p.seq < 0) return {AddStatus::kRejected, who + ": negative seq at index " + std::to_string(i)};
    if (i > 0 && p.seq <= update.poses[i - 1].seq) {
      return {AddStatus::kRejected,
              who + ": seq " + std::to_string(p.seq) + " not ascending at index " + std::to_string(i)};
    }
    if (!finite(p.T_local_base))
      return {AddStatus::kRejected, who + ": non-finite pose of seq " + std::to_string(p.seq)};
  }
  agent_poses_.erase(agent_poses_.lower_bound(KeyframeId{update.robot, 0}),
                     agent_poses_.upper_bound(KeyframeId{update.robot, INT32_MAX}));
  for (const KeyframePose& p : update.poses) agent_poses_.emplace(KeyframeId{update.robot, p.seq}, p.T_local_base);
  own_frames_.erase(update.robot);       // re-solved on the new chain at the next optimize()
  chains_changed_.insert(update.robot);  // its edges in the global graph: update_graph()
  ++version_;
  return {AddStatus::kAccepted, {}};
}

SE2 MultiRobotMapper::agent_local_pose(KeyframeId id) const {
  const Keyframe& kf = keyframes_.at(id);
  // The latest keyframe at or before id that the agent's estimate covers and that is stored.
  for (auto it = agent_poses_.upper_bound(id); it != agent_poses_.begin();) {
    --it;
    if (it->first.robot != id.robot) break;
    auto stored = keyframes_.find(it->first);
    if (stored != keyframes_.end()) return it->second * stored->second.T_local_base.between(kf.T_local_base);
  }
  return kf.T_local_base;
}

SE2 MultiRobotMapper::correction(RobotId robot) const {
  auto it = optimized_.upper_bound(KeyframeId{robot, INT32_MAX});
  if (it != optimized_.begin()) {
    --it;
    auto kf = keyframes_.find(it->first);
    if (it->first.robot == robot && kf != keyframes_.end()) {
      return it->second * kf->second.T_local_base.inverse();
    }
  }
  return start_of(robot);
}

PoseGraphEdge MultiRobotMapper::chain_edge(const Keyframe& prev, const Keyframe& kf, bool* gap) const {
  PoseGraphEdge edge{prev.id, kf.id, {}, {}, EdgeKind::kOdometry};
  const int steps = kf.id.seq - prev.id.seq;
  const auto info = information_of(kf.edge_covariance);
  *gap = steps != 1 || !info;
  if (!*gap) {
    const auto a = agent_poses_.find(prev.id), b = agent_poses_.find(kf.id);
    edge.T_from_to = a != agent_poses_.end() && b != agent_poses_.end() ? a->second.between(b->second) : kf.T_prev_this;
    edge.information = *info;
  } else {
    edge.T_from_to = agent_local_pose(prev.id).between(agent_local_pose(kf.id));
    edge.information = diag_information(options_.gap_sigma_xy_m_per_step * std::sqrt(double(steps)),
                                        options_.gap_sigma_yaw_rad_per_step * std::sqrt(double(steps)));
  }
  return edge;
}

void MultiRobotMapper::add_robot_chain(RobotId robot, OptimizeResult* result) {
  const SE2 T_global_local = correction(robot);
  const Keyframe* prev = nullptr;
  SE2 prev_initial;
  bool placed_new = false;
  auto it = first_unplaced(keyframes_, graph_, robot);
  if (it != keyframes_.begin() && std::prev(it)->first.robot == robot) {
    prev = &std::prev(it)->second;
    prev_initial = *graph_.estimate(prev->id);
  }
  for (; it != keyframes_.end() && it->first.robot == robot; ++it) {
    const Keyframe& kf = it->second;
    if (graph_.has_node(kf.id)) {
      prev = &kf;
      prev_initial = *graph_.estimate(kf.id);
      continue;
    }
    bool gap = false;
    const PoseGraphEdge edge =
        prev ? chain_edge(*prev, kf, &gap) : PoseGraphEdge{kf.id, kf.id, {}, {}, EdgeKind::kOdometry};
    result->gap_edges += gap;
    auto opt = optimized_.find(kf.id);
    const SE2 initial = opt != optimized_.end() ? opt->second
                        : prev                  ? prev_initial * edge.T_from_to
                                                : T_global_local * kf.T_local_base;
    placed_new |= graph_.add_node(kf.id, initial);
    if (prev) {
      graph_.add_edge(edge);
    } else if (hints_.count(robot) || robot == anchor_) {
      graph_.set_prior(
          PosePrior{kf.id, start_of(robot) * kf.T_local_base,
                    diag_information(options_.start_prior_sigma_xy_m, options_.start_prior_sigma_yaw_rad)});
    }
    prev = &kf;
    prev_initial = initial;
  }
  // Only new nodes can lack landmark edges (a rebuilt graph makes every node new).
  if (placed_new) add_landmark_edges(robot);  // multi_robot_mapper_landmarks.cpp
}

std::optional<SE2> MultiRobotMapper::global_pose(KeyframeId id) const {
  auto kf = keyframes_.find(id);
  if (kf == keyframes_.end() || !linked(id.robot)) return std::nullopt;
  auto opt = optimized_.find(id);
  if (opt != optimized_.end()) return opt->second;
  return correction(id.robot) * kf->second.T_local_base;
}

Trajectory MultiRobotMapper::global_trajectory(RobotId robot) const {
  Trajectory trajectory;
  if (!linked(robot)) return trajectory;
  for (auto it = keyframes_.lower_bound(KeyframeId{robot, 0}); it != keyframes_.end() && it->first.robot == robot;
       ++it) {
    trajectory.push_back(StampedPose{it->second.stamp_ns, *global_pose(it->first)});
  }
  return trajectory;
}

std::vector<RobotSummary> MultiRobotMapper::robots() const {
  std::map<RobotId, RobotSummary> out;
  auto entry = [&](RobotId id) -> RobotSummary& {
    RobotSummary& s = out[id];
    s.id = id;
    s.linked = linked(id);
    s.anchor = anchor_ && *anchor_ == id;
    return s;
  };
  for (const auto& [id, start] : starts_) entry(id);
  for (const auto& [id, kf] : keyframes_) {
    RobotSummary& s = entry(id.robot);
    ++s.keyframes;
    s.last_stamp_ns = std::max(s.last_stamp_ns, kf.stamp_ns);
    s.last_seq = std::max(s.last_seq, id.seq);
  }
  for (const auto& [id, report] : reports_) ++entry(id.robot).objects;
  for (const LoopClosure& c : loops_) {
    if (c.a.robot == c.b.robot) continue;
    ++entry(c.a.robot).inter_robot_closures;
    ++entry(c.b.robot).inter_robot_closures;
  }
  std::vector<RobotSummary> list;
  for (auto& [id, s] : out) {
    s.missing_keyframes = s.last_seq + 1 - s.keyframes;
    if (s.linked) s.T_global_local = correction(id);
    list.push_back(s);
  }
  return list;
}

void MultiRobotMapper::update_graph(OptimizeResult* result) {
  if (!options_.incremental_graph) rebuild_graph_ = true;  // mapper_options.h: why
  refresh_object_constraints();                            // multi_robot_mapper_objects.cpp; may set rebuild_graph_
  if (rebuild_graph_) {
    graph_ = PoseGraph2d(options_.graph);
    loop_in_graph_.assign(loops_.size(), false);
    object_edges_in_graph_.clear();
    rebuild_graph_ = false;
  }
  // Chains re-measured by their agents' loop closing: edge measurements replaced in place (the
  // live problem is kept), then a full warm-started solve. O(edges), no rebuild.
  if (!chains_changed_.empty()) {
    const std::vector<PoseGraphEdge>& edges = graph_.edges();
    for (size_t i = 0; i < edges.size(); ++i) {
      const PoseGraphEdge& e = edges[i];
      if (e.kind != EdgeKind::kOdometry || e.from.robot != e.to.robot || !chains_changed_.count(e.from.robot)) continue;
      bool gap = false;
      const PoseGraphEdge chain = chain_edge(keyframes_.at(e.from), keyframes_.at(e.to), &gap);
      graph_.set_edge_measurement(i, chain.T_from_to, chain.information);
    }
    refine_pending_ = true;
    chains_changed_.clear();
  }
  // New keyframes of each linked robot (O(robots + new keyframes), not O(keyframes)).
  const int window = std::max(0, options_.incremental_window_keyframes);
  std::vector<KeyframeId> active;
  for (auto it = keyframes_.begin(); it != keyframes_.end();
       it = keyframes_.upper_bound(KeyframeId{it->first.robot, INT32_MAX})) {
    const RobotId robot = it->first.robot;
    if (!linked(robot)) {
      ++result->unlinked_robots;
      continue;
    }
    append_window(keyframes_, robot, first_unplaced(keyframes_, graph_, robot), window, &active);
    add_robot_chain(robot, result);
  }
  const size_t edges_before = graph_.edges().size();
  const size_t landmark_edges_before = graph_.landmark_edges().size();
  add_loop_edges();
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
  PoseGraphSolveOptions solve = options_.solve;
  if (full_resolve_) {
    updates_since_refine_ = 0;
    if (const auto init = lago_initialize(graph_)) graph_.set_estimates(*init);
    result->full_resolve = true;
    full_resolve_ = false;
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
    for (KeyframeId id : active) optimized_[id] = *graph_.estimate(id);
    map_moved_.insert(map_moved_.end(), active.begin(), active.end());
  } else if (!refine_now) {
    result->solve.converged = true;
    result->solve.reason = "nothing new";
  }
  if (refine_now) {
    updates_since_refine_ = 0;
    solve.max_time_s = options_.refine_max_time_s;
    result->solve = graph_.solve(solve);
    result->full_solve = true;
    refine_pending_ = !result->solve.converged;
    for (const auto& [id, pose] : graph_.estimates()) optimized_[id] = pose;
    map_all_moved_ = true;
  }
}

OptimizeResult MultiRobotMapper::optimize() {
  OptimizeResult result;
  choose_anchor();
  if (options_.detect_loops) {
    detect_new_loops(&result);
    refresh_own_frames();  // multi_robot_mapper_linking.cpp
    link_robot_pairs(&result);
  }
  place_new_robots();
  release_held_closures(&result);
  update_graph(&result);
  result.nodes = int(graph_.num_nodes());
  result.edges = int(graph_.edges().size());
  result.priors = int(graph_.priors().size());
  result.object_edges = int(object_edges_in_graph_.size());
  result.constrained_objects = int(graph_.object_estimates().size());
  for (size_t i = 0; i < loops_.size(); ++i) {
    if (!loop_in_graph_[i]) continue;
    ++result.loop_closures;
    result.inter_robot_closures += loops_[i].a.robot != loops_[i].b.robot;
  }
  if (result.full_resolve) {
    for (const auto& [id, pose] : graph_.estimates()) optimized_[id] = pose;
    map_all_moved_ = true;
  }
  if (map_moved_.size() > keyframes_.size()) map_all_moved_ = true;  // never rendered: bound the list
  if (map_all_moved_) map_moved_.clear();
  note_poses_changed();
  ++version_;
  return result;
}

void MultiRobotMapper::note_poses_changed() {
  if (tracked_poses_version_ == poses_version_) ++tracked_poses_version_;
  ++poses_version_;
}

const OccupancyGrid& MultiRobotMapper::global_map() const {
  if (map_version_ == poses_version_) return map_.render();
  // The renderer redraws only the tiles of keyframes that are new, gone or moved beyond its
  // thresholds; here only keyframes whose pose may have changed are handed to it.
  std::map<RobotId, SE2> corrections;
  for (const auto& [id, start] : starts_) corrections[id] = correction(id);
  auto place = [&](const Keyframe& kf, const SE2* optimised) {
    auto c = corrections.find(kf.id.robot);
    if (c == corrections.end()) {  // not linked: not placed
      map_.remove(kf.id);
    } else {
      map_.set_pose(kf, optimised ? *optimised : c->second * kf.T_local_base);
    }
  };
  if (map_all_moved_ || tracked_poses_version_ != poses_version_) {
    auto opt = optimized_.begin();  // one merge pass: both maps are in id order
    for (const auto& [id, kf] : keyframes_) {
      while (opt != optimized_.end() && opt->first < id) ++opt;
      place(kf, opt != optimized_.end() && opt->first == id ? &opt->second : nullptr);
    }
  } else {
    for (KeyframeId id : map_moved_) {
      auto kf = keyframes_.find(id);
      auto opt = optimized_.find(id);
      if (kf != keyframes_.end()) place(kf->second, opt != optimized_.end() ? &opt->second : nullptr);
    }
  }
  map_moved_.clear();
  map_all_moved_ = false;
  tracked_poses_version_ = poses_version_;
  map_version_ = poses_version_;
  return map_.render();
}

}  // namespace cairn::base
