// MultiRobotMapper: object reports, placed through their anchor keyframes and merged in the global
// frame by merge_object_reports (global_object.h: overlap candidates verified by RGB-ICP); and the
// merged objects as pose-graph constraints (object_constraints.h).
// Feedback loop: the merge depends on the placements, which depend on the graph, which the merged
// objects constrain. So the observations are recomputed from the current merge at every optimize()
// (a merge that no longer holds drops its edges), only ICP-verified merges count, their residuals
// have a robust loss, and they never link robots (only linked robots' reports are placed and
// merged). New observations are added to the live graph; a changed or removed one rebuilds it.
#include <algorithm>
#include <cmath>

#include "base_station/core/multi_robot_mapper.h"
#include "base_station/core/robot_frame_objects.h"

namespace cairn::base {
namespace {

std::string validate(const ObjectReport& r) {
  if (!r.id.robot.valid()) return "invalid robot id " + std::to_string(r.id.robot.value);
  if (r.id.seq < 0) return "invalid object seq " + std::to_string(r.id.seq);
  if (r.anchor_seq < 0) return "invalid anchor seq " + std::to_string(r.anchor_seq);
  if (!r.T_anchor_object.matrix().allFinite()) return "non-finite pose T_anchor_object";
  if (!r.covariance.allFinite()) return "non-finite covariance";
  if (!std::isfinite(r.confidence)) return "non-finite confidence";
  if (!r.size_m.allFinite()) return "non-finite size";
  if (r.class_name.empty()) return "empty class name";
  return {};
}

}  // namespace

AddResult MultiRobotMapper::add_object(const ObjectReport& report) {
  const std::string invalid = validate(report);
  if (!invalid.empty()) return {AddStatus::kRejected, to_string(report.id) + ": " + invalid};
  auto existing = data_.reports.find(report.id);
  if (existing != data_.reports.end() && existing->second.class_name != report.class_name) {
    // A track never changes its class: another object under a stored one's id (a restarted or
    // spoofed robot reusing its ids) must not replace it.
    return {AddStatus::kConflict, to_string(report.id) + " is stored as a " + existing->second.class_name + ": a " +
                                      report.class_name + " under its id is refused"};
  }
  if (existing != data_.reports.end() && existing->second.stamp_ns > report.stamp_ns) {
    return {AddStatus::kDuplicate, to_string(report.id) + ": older than the stored report"};
  }
  ObjectReport stored = report;
  const size_t before = stored.cloud.size();
  stored.cloud.erase(std::remove_if(stored.cloud.begin(), stored.cloud.end(),
                                    [](const ColoredPoint& p) {
                                      return !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z);
                                    }),
                     stored.cloud.end());
  AddResult result{AddStatus::kAccepted, {}};
  if (stored.cloud.size() != before) {
    result.reason = "dropped " + std::to_string(before - stored.cloud.size()) + " non-finite cloud points; ";
  }
  const KeyframeId anchor{report.id.robot, report.anchor_seq};
  if (!data_.keyframes.count(anchor)) {
    result.status = AddStatus::kPending;
    result.reason += "anchor " + to_string(anchor) + " not received yet";
  } else if (!linked(report.id.robot)) {
    result.status = AddStatus::kPending;
    result.reason += to_string(report.id.robot) + " not linked: kept, not placed";
  }
  data_.reports[report.id] = std::move(stored);
  ++version_;
  return result;
}

std::vector<GlobalObject> MultiRobotMapper::objects() const {
  refresh_objects();
  return objects_;
}

std::vector<GlobalObject> MultiRobotMapper::unplaced_objects() const {
  refresh_objects();
  return unplaced_;
}

std::vector<ObjectIdRegistry::Entry> MultiRobotMapper::take_object_id_entries() {
  return object_ids_.take_new_entries();
}

void MultiRobotMapper::refresh_objects() const {
  if (objects_version_ == version_) return;
  // Placed and unplaced together through the registry: an object keeps its id when its robot links.
  std::vector<GlobalObject> all = compute_objects();
  for (GlobalObject& o : robot_frame_objects(data_, merge_options())) all.push_back(std::move(o));
  object_ids_.assign(&all);
  objects_.clear();
  unplaced_.clear();
  for (GlobalObject& o : all) (o.frame.valid() ? unplaced_ : objects_).push_back(std::move(o));
  objects_version_ = version_;
}

void MultiRobotMapper::refresh_object_constraints() {
  std::vector<ObjectConstraint> now;
  if (options_.object_constraints.enabled && !data_.reports.empty()) {
    now = object_constraints(objects(), data_.reports, options_.object_constraints, options_.object_merge);
  }
  if (same_constraints(now, object_constraints_)) return;
  auto by_report = [](const std::vector<ObjectConstraint>& list, ObjectId report) {
    auto it = std::lower_bound(list.begin(), list.end(), report,
                               [](const ObjectConstraint& c, ObjectId id) { return c.report < id; });
    return it != list.end() && it->report == report ? &*it : nullptr;
  };
  // Residual blocks cannot be taken out of the live graph: an observation in it that changed or
  // went away rebuilds the graph (warm-started from the last solution).
  for (ObjectId report : object_edges_in_graph_) {
    const ObjectConstraint* before = by_report(object_constraints_, report);
    const ObjectConstraint* after = by_report(now, report);
    if (!before || !after || !same_constraints({*before}, {*after})) {
      rebuild_graph_ = true;
      break;
    }
  }
  object_constraints_ = std::move(now);
}

void MultiRobotMapper::add_object_edges() {
  for (const ObjectConstraint& c : object_constraints_) {
    if (object_edges_in_graph_.count(c.report) || !graph_.has_node(c.edge.from)) continue;
    if (graph_.add_landmark_edge(c.edge)) object_edges_in_graph_.insert(c.report);
  }
}

std::vector<GlobalObject> MultiRobotMapper::compute_objects() const {
  std::vector<PlacedObjectReport> placed;
  for (const auto& [id, r] : data_.reports) {
    const std::optional<SE2> anchor = data_.global_pose(KeyframeId{id.robot, r.anchor_seq});
    if (!anchor) continue;  // pending anchor or unlinked robot
    placed.push_back(PlacedObjectReport{&r, anchor->to_isometry3() * r.T_anchor_object});
  }
  // Candidates by overlap, verified by RGB-ICP in the global frame (global_object.h).
  return merge_object_reports(placed, merge_options());
}

ObjectMergeOptions MultiRobotMapper::merge_options() const {
  ObjectMergeOptions merge = options_.object_merge;
  merge.max_gate_m = options_.merge_distance_m;
  merge.object_voxel_m = options_.object_voxel_m;
  return merge;
}

}  // namespace cairn::base
