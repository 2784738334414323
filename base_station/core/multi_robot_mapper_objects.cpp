// MultiRobotMapper: object reports and their merging in the global frame.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "base_station/core/multi_robot_mapper.h"

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

/// A report placed in the global frame.
struct PlacedReport {
  const ObjectReport* report;
  Eigen::Isometry3d T_global_object;
};

int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

/// Groups reports of the same class whose centroids are within merge_distance_m (union-find).
std::vector<std::vector<int>> cluster(const std::vector<PlacedReport>& placed, double merge_distance_m) {
  std::vector<int> parent(placed.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (size_t i = 0; i < placed.size(); ++i) {
    for (size_t j = i + 1; j < placed.size(); ++j) {
      if (placed[i].report->class_name != placed[j].report->class_name) continue;
      const double d = (placed[i].T_global_object.translation() - placed[j].T_global_object.translation()).norm();
      if (d > merge_distance_m) continue;
      const int a = find_root(parent, int(i)), b = find_root(parent, int(j));
      parent[std::max(a, b)] = std::min(a, b);  // smallest index (= smallest ObjectId) is the root
    }
  }
  std::vector<std::vector<int>> groups(placed.size());
  for (size_t i = 0; i < placed.size(); ++i) groups[find_root(parent, int(i))].push_back(int(i));
  groups.erase(std::remove_if(groups.begin(), groups.end(), [](const auto& g) { return g.empty(); }),
               groups.end());
  return groups;
}

GlobalObject merge(const std::vector<PlacedReport>& placed, const std::vector<int>& members, double voxel_m) {
  GlobalObject o;
  const ObjectReport& first = *placed[members.front()].report;
  o.id = first.id;
  o.class_name = first.class_name;
  double weight_sum = 0.0;
  const ObjectReport* best = &first;
  ColoredCloud cloud;
  for (int i : members) {
    const ObjectReport& r = *placed[i].report;
    const Eigen::Isometry3d& T = placed[i].T_global_object;
    const double w = std::max(1, r.observations);
    o.position_m += w * T.translation();
    weight_sum += w;
    o.confidence = std::max(o.confidence, r.confidence);
    o.size_m = o.size_m.cwiseMax(r.size_m);
    o.observations += r.observations;
    o.last_stamp_ns = std::max(o.last_stamp_ns, r.stamp_ns);
    o.reports.push_back(r.id);
    o.robots.push_back(r.id.robot);
    if (r.confidence > best->confidence || (r.confidence == best->confidence && r.stamp_ns > best->stamp_ns)) {
      best = &r;
    }
    for (const ColoredPoint& p : r.cloud) {
      const Eigen::Vector3d q = T * Eigen::Vector3d(p.x, p.y, p.z);
      cloud.push_back(ColoredPoint{float(q.x()), float(q.y()), float(q.z()), p.r, p.g, p.b});
    }
  }
  o.position_m /= weight_sum;
  // Covariance of the weighted mean (reports' position covariances rotated to the global frame)
  // plus the weighted scatter of the reports around it.
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (int i : members) {
    const ObjectReport& r = *placed[i].report;
    const Eigen::Matrix3d R = placed[i].T_global_object.linear();
    const double w = std::max(1, r.observations) / weight_sum;
    const Eigen::Vector3d d = placed[i].T_global_object.translation() - o.position_m;
    cov += w * w * (R * r.covariance.topLeftCorner<3, 3>() * R.transpose()) + w * d * d.transpose();
  }
  o.covariance = cov;
  std::sort(o.robots.begin(), o.robots.end());
  o.robots.erase(std::unique(o.robots.begin(), o.robots.end()), o.robots.end());
  o.thumbnail_jpeg = best->thumbnail_jpeg;
  o.cloud_global = voxel_downsample(cloud, voxel_m);
  return o;
}

}  // namespace

AddResult MultiRobotMapper::add_object(const ObjectReport& report) {
  const std::string invalid = validate(report);
  if (!invalid.empty()) return {AddStatus::kRejected, to_string(report.id) + ": " + invalid};
  auto existing = reports_.find(report.id);
  if (existing != reports_.end() && existing->second.stamp_ns > report.stamp_ns) {
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
  if (!keyframes_.count(anchor)) {
    result.status = AddStatus::kPending;
    result.reason += "anchor " + to_string(anchor) + " not received yet";
  } else if (!linked(report.id.robot)) {
    result.status = AddStatus::kPending;
    result.reason += to_string(report.id.robot) + " not linked: kept, not placed";
  }
  reports_[report.id] = std::move(stored);
  ++version_;
  return result;
}

std::vector<ObjectId> MultiRobotMapper::pending_objects() const {
  std::vector<ObjectId> out;
  for (const auto& [id, r] : reports_) {
    if (!keyframes_.count(KeyframeId{id.robot, r.anchor_seq})) out.push_back(id);
  }
  return out;
}

std::vector<GlobalObject> MultiRobotMapper::objects() const {
  if (objects_version_ != version_) {
    objects_ = compute_objects();
    objects_version_ = version_;
  }
  return objects_;
}

std::vector<GlobalObject> MultiRobotMapper::compute_objects() const {
  std::vector<PlacedReport> placed;
  for (const auto& [id, r] : reports_) {
    const std::optional<SE2> anchor = global_pose(KeyframeId{id.robot, r.anchor_seq});
    if (!anchor) continue;  // pending anchor or unlinked robot
    placed.push_back(PlacedReport{&r, anchor->to_isometry3() * r.T_anchor_object});
  }
  std::vector<GlobalObject> out;
  for (const std::vector<int>& members : cluster(placed, options_.merge_distance_m)) {
    out.push_back(merge(placed, members, options_.object_voxel_m));
  }
  std::sort(out.begin(), out.end(), [](const GlobalObject& a, const GlobalObject& b) { return a.id < b.id; });
  return out;
}

}  // namespace cairn::base
