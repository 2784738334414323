// MultiRobotMapper: ingest, optimize() step by step, and what the outputs read (see
// multi_robot_mapper.h). The graph update is in multi_robot_mapper_graph.cpp, objects in
// multi_robot_mapper_objects.cpp, link decisions in robot_linker*.cpp.
#include "base_station/core/multi_robot_mapper.h"

#include <algorithm>
#include <climits>
#include <cmath>

#include "base_station/core/robot_frame_objects.h"

namespace cairn::base {
namespace {

bool finite(const SE2& T) { return T.vector().allFinite(); }

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
    case AddStatus::kConflict:
      return "conflict";
  }
  return "unknown";
}

MultiRobotMapper::MultiRobotMapper(const MapperOptions& options)
    : options_(options), linker_(options), graph_(options.graph), map_(options.grid, map_render_options(options)) {}

void MultiRobotMapper::set_robot_start(RobotId robot, const SE2& T_global_local) {
  if (!robot.valid() || !finite(T_global_local)) return;
  data_.starts[robot] = T_global_local;
  data_.hints[robot] = T_global_local;
  rebuild_graph_ = true;
  // Earlier solutions of this robot were relative to another start: re-initialise from the new one.
  for (auto it = data_.optimized.begin(); it != data_.optimized.end();) {
    it = it->first.robot == robot ? data_.optimized.erase(it) : std::next(it);
  }
  map_.all_moved();
  map_.poses_changed();
  ++version_;
}

bool MultiRobotMapper::set_entry_hint(RobotId robot, const EntryHint& hint) {
  if (!robot.valid() || !finite(hint.T_global_local) || !(hint.sigma_xy_m > 0) || !(hint.sigma_yaw_rad > 0) ||
      !std::isfinite(hint.sigma_xy_m) || !std::isfinite(hint.sigma_yaw_rad))
    return false;
  data_.entry_hints[robot] = hint;
  return true;
}

bool MultiRobotMapper::request_alignment(RobotId robot, const SE2& T_global_local) {
  if (!robot.valid() || !finite(T_global_local)) return false;
  linker_.request_alignment(robot, T_global_local);
  return true;
}

AddResult MultiRobotMapper::add_keyframe(const Keyframe& kf) {
  const std::string invalid = validate(kf);
  if (!invalid.empty()) return {AddStatus::kRejected, to_string(kf.id) + ": " + invalid};
  if (const auto stored = data_.keyframes.find(kf.id); stored != data_.keyframes.end()) {
    // The same keyframe again (a resend) is a duplicate; another one under its id must not replace it.
    const Keyframe& old = stored->second;
    const bool same = old.stamp_ns == kf.stamp_ns && old.scan.ranges_m.size() == kf.scan.ranges_m.size() &&
                      (old.T_local_base.translation() - kf.T_local_base.translation()).norm() < 1e-6;
    if (same) return {AddStatus::kDuplicate, to_string(kf.id) + " already stored"};
    return {AddStatus::kConflict, to_string(kf.id) + " already stored with another stamp, pose or scan: refused"};
  }
  data_.keyframes.emplace(kf.id, kf);
  data_.latest_stamp_ns = std::max(data_.latest_stamp_ns, kf.stamp_ns);
  ++version_;
  if (linker_.note_keyframe(kf, &data_)) map_.all_moved();  // the provisional anchor changed
  if (graph_.has_node(kf.id)) rebuild_graph_ = true;
  auto next = data_.keyframes.upper_bound(kf.id);
  if (next != data_.keyframes.end() && next->first.robot == kf.id.robot && graph_.has_node(next->first)) {
    rebuild_graph_ = true;  // arrived after its successor: the gap edge must go
  }
  if (!linked(kf.id.robot)) {
    return {AddStatus::kPending,
            to_string(kf.id.robot) +
                " not linked to the others yet (waiting for verified inter-robot loop closures): kept, not placed"};
  }
  map_.moved(kf.id);
  map_.poses_changed();
  AddResult result{AddStatus::kAccepted, {}};
  if (kf.id.seq > 0 && !data_.keyframes.count(KeyframeId{kf.id.robot, kf.id.seq - 1})) {
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
  data_.agent_poses.erase(data_.agent_poses.lower_bound(KeyframeId{update.robot, 0}),
                          data_.agent_poses.upper_bound(KeyframeId{update.robot, INT32_MAX}));
  for (const KeyframePose& p : update.poses) data_.agent_poses.emplace(KeyframeId{update.robot, p.seq}, p.T_local_base);
  data_.own_frames.erase(update.robot);  // re-solved on the new chain at the next optimize()
  chains_changed_.insert(update.robot);  // its edges in the global graph: update_graph()
  ++version_;
  return {AddStatus::kAccepted, {}};
}

OptimizeResult MultiRobotMapper::optimize() {
  OptimizeResult result;
  // 1. Decide which robots are placed where (anchor, markers, loop closures, PCM, map checks).
  LinkUpdate links = linker_.update(&data_);
  if (links.placements_changed) map_.poses_changed_unlisted();
  result.newly_linked = std::move(links.newly_linked);
  result.link_events = std::move(links.events);
  result.pending_candidates = links.pending_candidates;
  note_link_times();
  // 2. Bring the linked robots' new keyframes and the accepted constraints into the graph; solve.
  update_graph(links.full_resolve, &result);
  count_graph(&result);
  // 3. Publish the solution to what the outputs read.
  if (result.full_resolve) {
    for (const auto& [id, pose] : graph_.estimates()) data_.optimized[id] = pose;
    map_.all_moved();
  }
  map_.bound(data_.keyframes.size());
  map_.poses_changed();
  ++version_;
  return result;
}

void MultiRobotMapper::note_link_times() {
  for (auto it = data_.linked_at_ns.begin(); it != data_.linked_at_ns.end();) {  // a provisional anchor replaced
    it = data_.linked(it->first) ? std::next(it) : data_.linked_at_ns.erase(it);
  }
  for (const auto& [robot, start] : data_.starts) {
    const RobotKeyframes own = data_.robot_keyframes(robot);
    if (data_.linked_at_ns.count(robot) || own.empty()) continue;
    const bool from_start = data_.anchor == robot || data_.hints.count(robot);
    data_.linked_at_ns[robot] = from_start ? own.begin()->second.stamp_ns : data_.latest_stamp_ns;
  }
}

void MultiRobotMapper::count_graph(OptimizeResult* result) const {
  result->nodes = int(graph_.num_nodes());
  result->edges = int(graph_.edges().size());
  result->priors = int(graph_.priors().size());
  result->object_edges = int(object_edges_in_graph_.size());
  result->constrained_objects = int(graph_.object_estimates().size());
  for (size_t i = 0; i < data_.loops.size(); ++i) {
    if (!loop_in_graph_[i]) continue;
    ++result->loop_closures;
    result->inter_robot_closures += data_.loops[i].a.robot != data_.loops[i].b.robot;
  }
  for (RobotId robot : data_.keyframe_robots()) result->unlinked_robots += !linked(robot);
}

std::vector<RobotSummary> MultiRobotMapper::robots() const {
  std::map<RobotId, RobotSummary> out;
  auto entry = [&](RobotId id) -> RobotSummary& {
    RobotSummary& s = out[id];
    s.id = id;
    s.linked = linked(id);
    s.anchor = data_.anchor && *data_.anchor == id;
    return s;
  };
  for (const auto& [id, start] : data_.starts) entry(id);
  for (const auto& [id, kf] : data_.keyframes) {
    RobotSummary& s = entry(id.robot);
    if (s.keyframes == 0) s.first_stamp_ns = kf.stamp_ns;  // keyframes are in seq order per robot
    ++s.keyframes;
    s.last_stamp_ns = std::max(s.last_stamp_ns, kf.stamp_ns);
    s.last_seq = std::max(s.last_seq, id.seq);
  }
  for (const auto& [id, report] : data_.reports) ++entry(id.robot).objects;
  for (const LoopClosure& c : data_.loops) {
    if (c.a.robot == c.b.robot) continue;
    ++entry(c.a.robot).inter_robot_closures;
    ++entry(c.b.robot).inter_robot_closures;
  }
  std::vector<RobotSummary> list;
  for (auto& [id, s] : out) {
    s.missing_keyframes = s.last_seq + 1 - s.keyframes;
    if (s.linked) s.T_global_local = data_.correction(id);
    const auto linked_at = data_.linked_at_ns.find(id);
    if (linked_at != data_.linked_at_ns.end()) s.time_to_link_s = ns_to_sec(linked_at->second - s.first_stamp_ns);
    list.push_back(s);
  }
  return list;
}

const std::vector<RobotFrameMap>& MultiRobotMapper::robot_frame_maps() const {
  if (frame_maps_version_ == version_) return frame_maps_;
  const std::vector<GlobalObject> unplaced = unplaced_objects();
  std::vector<RobotFrameMap> maps;
  for (RobotId robot : data_.keyframe_robots()) {
    if (linked(robot)) {
      frame_renderers_.erase(robot);  // placed on the global map now
      continue;
    }
    auto renderer = frame_renderers_.find(robot);
    if (renderer == frame_renderers_.end())
      renderer = frame_renderers_.emplace(robot, GlobalMapRenderer(options_.grid, map_render_options(options_))).first;
    maps.emplace_back();
    update_robot_frame_map(data_, robot, unplaced, &renderer->second, &maps.back());
  }
  frame_maps_ = std::move(maps);
  frame_maps_version_ = version_;
  return frame_maps_;
}

MergedMap MultiRobotMapper::merged() const {
  MergedMap m;
  m.grid = &global_map();
  m.data = &data_;
  m.graph = &graph_;
  m.robots = robots();
  for (const RobotSummary& r : m.robots) {
    if (r.linked) m.trajectories[r.id] = data_.global_trajectory(r.id);
  }
  m.objects = objects();
  m.unplaced_objects = unplaced_objects();
  m.robot_frame_maps = &robot_frame_maps();
  m.alignments = linker_.alignments();
  m.version = version_;
  return m;
}

}  // namespace cairn::base
