#include "base_station/core/multi_robot_mapper.h"

#include <Eigen/Cholesky>
#include <climits>
#include <cmath>
#include <set>

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

/// Adds the ray-cast of one keyframe's scan (hits and no-return beams) to `grid`.
void insert_keyframe_scan(const Keyframe& kf, const SE2& T_global_base, double no_return_range_m,
                          OccupancyGrid* grid) {
  const std::vector<Eigen::Vector2f> hits = scan_to_points(kf.scan);
  std::vector<Eigen::Vector2f> no_return;
  const float clear_m = float(std::min<double>(kf.scan.range_max_m, no_return_range_m));
  for (size_t i = 0; i < kf.scan.ranges_m.size(); ++i) {
    const float r = kf.scan.ranges_m[i];
    if (std::isnan(r) || r < kf.scan.range_max_m) continue;  // +inf and >= max: no return
    const float a = beam_angle_rad(kf.scan, i);
    no_return.emplace_back(clear_m * std::cos(a), clear_m * std::sin(a));
  }
  grid->insert_scan(T_global_base, hits, no_return);
}

}  // namespace

const char* to_string(AddStatus status) {
  switch (status) {
    case AddStatus::kAccepted: return "accepted";
    case AddStatus::kPending: return "pending";
    case AddStatus::kDuplicate: return "duplicate";
    case AddStatus::kRejected: return "rejected";
  }
  return "unknown";
}

MultiRobotMapper::MultiRobotMapper(const MapperOptions& options)
    : options_(options), loop_closer_(options.loop_closer), graph_(options.graph), map_(options.grid) {}

void MultiRobotMapper::set_robot_start(RobotId robot, const SE2& T_global_local) {
  if (!robot.valid() || !finite(T_global_local)) return;
  starts_[robot] = T_global_local;
  hints_[robot] = T_global_local;
  rebuild_graph_ = true;
  // Earlier solutions of this robot were relative to another start: re-initialise from the new one.
  for (auto it = optimized_.begin(); it != optimized_.end();) {
    it = it->first.robot == robot ? optimized_.erase(it) : std::next(it);
  }
  ++poses_version_;
  ++version_;
}

AddResult MultiRobotMapper::add_keyframe(const Keyframe& kf) {
  const std::string invalid = validate(kf);
  if (!invalid.empty()) return {AddStatus::kRejected, to_string(kf.id) + ": " + invalid};
  if (keyframes_.count(kf.id)) return {AddStatus::kDuplicate, to_string(kf.id) + " already stored"};
  keyframes_.emplace(kf.id, kf);
  detect_queue_.push_back(kf.id);
  ++version_;
  if (graph_.has_node(kf.id)) rebuild_graph_ = true;
  auto next = keyframes_.upper_bound(kf.id);
  if (next != keyframes_.end() && next->first.robot == kf.id.robot && graph_.has_node(next->first)) {
    rebuild_graph_ = true;  // arrived after its successor: the gap edge must go
  }
  if (!anchor_committed_ && hints_.empty() && (!anchor_ || kf.id.robot < *anchor_)) {
    if (anchor_) starts_.erase(*anchor_);
    anchor_ = kf.id.robot;
    starts_[kf.id.robot] = SE2();
  }
  if (!linked(kf.id.robot)) {
    return {AddStatus::kPending, to_string(kf.id.robot) +
                                     " not linked to the others yet (waiting for verified inter-robot loop closures): kept, not placed"};
  }
  ++poses_version_;
  AddResult result{AddStatus::kAccepted, {}};
  if (kf.id.seq > 0 && !keyframes_.count(KeyframeId{kf.id.robot, kf.id.seq - 1})) {
    result.reason = "predecessor seq " + std::to_string(kf.id.seq - 1) +
                    " missing: linked by local pose until it arrives";
  } else if (kf.id.seq > 0 && !information_of(kf.edge_covariance)) {
    result.reason = "edge covariance not positive definite: gap uncertainty used";
  }
  return result;
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

void MultiRobotMapper::add_robot_chain(RobotId robot, OptimizeResult* result) {
  const SE2 T_global_local = correction(robot);
  const Keyframe* prev = nullptr;
  SE2 prev_initial;
  for (auto it = keyframes_.lower_bound(KeyframeId{robot, 0});
       it != keyframes_.end() && it->first.robot == robot; ++it) {
    const Keyframe& kf = it->second;
    if (graph_.has_node(kf.id)) {
      prev = &kf;
      prev_initial = *graph_.estimate(kf.id);
      continue;
    }
    PoseGraphEdge edge{prev ? prev->id : kf.id, kf.id, {}, {}, EdgeKind::kOdometry};
    if (prev) {
      const int steps = kf.id.seq - prev->id.seq;
      const auto info = information_of(kf.edge_covariance);
      if (steps == 1 && info) {
        edge.T_from_to = kf.T_prev_this;
        edge.information = *info;
      } else {
        edge.T_from_to = prev->T_local_base.between(kf.T_local_base);
        edge.information = diag_information(options_.gap_sigma_xy_m_per_step * std::sqrt(double(steps)),
                                            options_.gap_sigma_yaw_rad_per_step * std::sqrt(double(steps)));
        ++result->gap_edges;
      }
    }
    auto opt = optimized_.find(kf.id);
    const SE2 initial = opt != optimized_.end() ? opt->second
                        : prev                  ? prev_initial * edge.T_from_to
                                                : T_global_local * kf.T_local_base;
    graph_.add_node(kf.id, initial);
    if (prev) {
      graph_.add_edge(edge);
    } else if (hints_.count(robot) || robot == anchor_) {
      graph_.set_prior(PosePrior{kf.id, start_of(robot) * kf.T_local_base,
                                 diag_information(options_.start_prior_sigma_xy_m,
                                                  options_.start_prior_sigma_yaw_rad)});
    }
    prev = &kf;
    prev_initial = initial;
  }
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
  for (auto it = keyframes_.lower_bound(KeyframeId{robot, 0});
       it != keyframes_.end() && it->first.robot == robot; ++it) {
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

const OccupancyGrid& MultiRobotMapper::global_map() const {
  if (map_version_ == poses_version_) return map_;
  map_ = OccupancyGrid(options_.grid);
  std::map<RobotId, SE2> corrections;
  for (const auto& [id, start] : starts_) corrections[id] = correction(id);
  for (const auto& [id, kf] : keyframes_) {
    auto c = corrections.find(id.robot);
    if (c == corrections.end()) continue;  // not linked: not placed
    auto opt = optimized_.find(id);
    const SE2 T_global_base = opt != optimized_.end() ? opt->second : c->second * kf.T_local_base;
    insert_keyframe_scan(kf, T_global_base, options_.no_return_clear_range_m, &map_);
  }
  map_version_ = poses_version_;
  return map_;
}

}  // namespace cairn::base
