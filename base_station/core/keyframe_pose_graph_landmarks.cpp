// KeyframePoseGraph: point nodes (markers and merged objects) and their range-bearing observations (see
// keyframe_pose_graph.h).
// The Ceres blocks are added by KeyframePoseGraph::sync_landmarks() in keyframe_pose_graph.cpp.
#include <cmath>

#include "base_station/core/keyframe_pose_graph.h"

namespace cairn::base {
namespace {

Eigen::Vector2d observed_point(const SE2& T_world_node, const LandmarkEdge& e) {
  return T_world_node * Eigen::Vector2d(e.range_m * std::cos(e.bearing_rad), e.range_m * std::sin(e.bearing_rad));
}

bool valid(const PointNodeId& id) {
  if (const auto* marker = std::get_if<LandmarkId>(&id)) return marker->valid();
  if (const auto* sighting = std::get_if<SightingNodeId>(&id)) return sighting->index >= 0;
  const ObjectId& object = std::get<ObjectId>(id);
  return object.robot.valid() && object.seq >= 0;
}

}  // namespace

std::string to_string(const PointNodeId& id) {
  if (const auto* marker = std::get_if<LandmarkId>(&id)) return to_string(*marker);
  if (const auto* sighting = std::get_if<SightingNodeId>(&id)) return "sighting " + std::to_string(sighting->index);
  return "object " + to_string(std::get<ObjectId>(id));
}

bool KeyframePoseGraph::add_landmark_edge(const LandmarkEdge& e) {
  if (!valid(e.landmark) || !nodes_.count(e.from)) return false;
  if (!std::isfinite(e.range_m) || !std::isfinite(e.bearing_rad) || e.range_m < 0.01) return false;
  if (!(e.sigma_range_m > 0) || !(e.sigma_bearing_rad > 0) || !std::isfinite(e.sigma_range_m) ||
      !std::isfinite(e.sigma_bearing_rad)) {
    return false;
  }
  if (!landmarks_.count(e.landmark)) {
    const Eigen::Vector2d p = observed_point(*estimate(e.from), e);
    landmarks_[e.landmark] = LandmarkState{{p.x(), p.y()}};
  }
  landmark_edges_.push_back(e);
  landmark_sources_.insert(e.from);
  return true;
}

std::optional<Eigen::Vector2d> KeyframePoseGraph::point_estimate(const PointNodeId& id) const {
  auto it = landmarks_.find(id);
  if (it == landmarks_.end()) return std::nullopt;
  return Eigen::Vector2d(it->second.p[0], it->second.p[1]);
}

std::map<LandmarkId, Eigen::Vector2d> KeyframePoseGraph::landmark_estimates() const {
  std::map<LandmarkId, Eigen::Vector2d> out;
  for (const auto& [id, l] : landmarks_) {
    if (const auto* marker = std::get_if<LandmarkId>(&id))
      out.emplace_hint(out.end(), *marker, Eigen::Vector2d(l.p[0], l.p[1]));
  }
  return out;
}

std::map<ObjectId, Eigen::Vector2d> KeyframePoseGraph::object_estimates() const {
  std::map<ObjectId, Eigen::Vector2d> out;
  for (const auto& [id, l] : landmarks_) {
    if (const auto* object = std::get_if<ObjectId>(&id))
      out.emplace_hint(out.end(), *object, Eigen::Vector2d(l.p[0], l.p[1]));
  }
  return out;
}

std::map<PointNodeId, Eigen::Vector2d> KeyframePoseGraph::point_estimates() const {
  std::map<PointNodeId, Eigen::Vector2d> out;
  for (const auto& [id, l] : landmarks_) out.emplace_hint(out.end(), id, Eigen::Vector2d(l.p[0], l.p[1]));
  return out;
}

void KeyframePoseGraph::initialize_landmarks() {
  std::map<PointNodeId, std::pair<Eigen::Vector2d, int>> sums;
  for (const LandmarkEdge& e : landmark_edges_) {
    auto& [sum, n] = sums.try_emplace(e.landmark, Eigen::Vector2d::Zero(), 0).first->second;
    sum += observed_point(*estimate(e.from), e);
    ++n;
  }
  for (const auto& [id, sn] : sums) {
    const Eigen::Vector2d mean = sn.first / double(sn.second);
    landmarks_.at(id) = LandmarkState{{mean.x(), mean.y()}};
  }
  landmarks_need_init_ = false;
}

}  // namespace cairn::base
