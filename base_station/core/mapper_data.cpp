#include "base_station/core/mapper_data.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <climits>
#include <cmath>

#include "common/check.h"

namespace cairn::base {

const Keyframe& MapperData::keyframe(KeyframeId id) const {
  const auto it = keyframes.find(id);
  CAIRN_CHECK(it != keyframes.end(), to_string(id) + " is not stored");
  return it->second;
}

RobotKeyframes MapperData::robot_keyframes(RobotId robot) const {
  return RobotKeyframes(keyframes.lower_bound(KeyframeId{robot, 0}),
                        keyframes.upper_bound(KeyframeId{robot, INT32_MAX}));
}

std::vector<ObjectId> MapperData::pending_objects() const {
  std::vector<ObjectId> out;
  for (const auto& [id, r] : reports) {
    if (!keyframes.count(KeyframeId{id.robot, r.anchor_seq})) out.push_back(id);
  }
  return out;
}

std::vector<RobotId> MapperData::keyframe_robots() const {
  std::vector<RobotId> robots;
  for (auto it = keyframes.begin(); it != keyframes.end();
       it = keyframes.upper_bound(KeyframeId{it->first.robot, INT32_MAX})) {
    robots.push_back(it->first.robot);
  }
  return robots;
}

SE2 MapperData::correction(RobotId robot) const {
  auto it = optimized.upper_bound(KeyframeId{robot, INT32_MAX});
  if (it != optimized.begin()) {
    --it;
    auto kf = keyframes.find(it->first);
    if (it->first.robot == robot && kf != keyframes.end()) return it->second * kf->second.T_local_base.inverse();
  }
  const auto start = starts.find(robot);
  CAIRN_CHECK(start != starts.end(), "correction of " + to_string(robot) + ", which is not linked");
  return start->second;
}

std::optional<SE2> MapperData::global_pose(KeyframeId id) const {
  auto kf = keyframes.find(id);
  if (kf == keyframes.end() || !linked(id.robot)) return std::nullopt;
  auto opt = optimized.find(id);
  if (opt != optimized.end()) return opt->second;
  return correction(id.robot) * kf->second.T_local_base;
}

Trajectory MapperData::global_trajectory(RobotId robot) const {
  Trajectory trajectory;
  if (!linked(robot)) return trajectory;
  for (const auto& [id, kf] : robot_keyframes(robot)) trajectory.push_back(StampedPose{kf.stamp_ns, *global_pose(id)});
  return trajectory;
}

SE2 MapperData::agent_local_pose(KeyframeId id) const {
  const Keyframe& kf = keyframe(id);
  // The latest keyframe at or before id that the agent's estimate covers and that is stored.
  for (auto it = agent_poses.upper_bound(id); it != agent_poses.begin();) {
    --it;
    if (it->first.robot != id.robot) break;
    auto stored = keyframes.find(it->first);
    if (stored != keyframes.end()) return it->second * stored->second.T_local_base.between(kf.T_local_base);
  }
  return kf.T_local_base;
}

SE2 MapperData::refined_local_pose(KeyframeId id) const {
  const Keyframe& kf = keyframe(id);
  if (linked(id.robot)) return correction(id.robot).inverse() * *global_pose(id);
  const auto frame = own_frames.find(id.robot);
  if (frame == own_frames.end()) return agent_local_pose(id);
  auto solved = frame->second.poses.upper_bound(id);  // the last solved keyframe at or before id
  if (solved == frame->second.poses.begin()) return agent_local_pose(id);
  --solved;
  return solved->second * keyframe(solved->first).T_local_base.between(kf.T_local_base);
}

std::optional<Eigen::Matrix3d> information_of(const Covariance3& covariance) {
  const Eigen::Matrix3d sym = 0.5 * (covariance + covariance.transpose());
  Eigen::LLT<Eigen::Matrix3d> llt(sym);
  if (llt.info() != Eigen::Success) return std::nullopt;
  const Eigen::Matrix3d info = llt.solve(Eigen::Matrix3d::Identity());
  if (!info.allFinite()) return std::nullopt;
  return info;
}

Eigen::Matrix3d diag_information(double sigma_xy_m, double sigma_yaw_rad) {
  return Eigen::Vector3d(1.0 / (sigma_xy_m * sigma_xy_m), 1.0 / (sigma_xy_m * sigma_xy_m),
                         1.0 / (sigma_yaw_rad * sigma_yaw_rad))
      .asDiagonal();
}

PoseGraphEdge chain_edge(const MapperData& data, const Keyframe& prev, const Keyframe& kf, const MapperOptions& options,
                         bool* gap) {
  PoseGraphEdge edge{prev.id, kf.id, {}, {}, EdgeKind::kOdometry};
  const int steps = kf.id.seq - prev.id.seq;
  Covariance3 covariance = kf.edge_covariance;  // diagonal raised to the floor: stays positive definite
  const double min_xy = options.chain_edge_min_sigma_xy_m * options.chain_edge_min_sigma_xy_m;
  const double min_yaw = options.chain_edge_min_sigma_yaw_rad * options.chain_edge_min_sigma_yaw_rad;
  for (int i = 0; i < 3; ++i) covariance(i, i) = std::max(covariance(i, i), i < 2 ? min_xy : min_yaw);
  const auto info = information_of(covariance);
  *gap = steps != 1 || !info;
  if (!*gap) {
    const auto a = data.agent_poses.find(prev.id), b = data.agent_poses.find(kf.id);
    edge.T_from_to =
        a != data.agent_poses.end() && b != data.agent_poses.end() ? a->second.between(b->second) : kf.T_prev_this;
    edge.information = *info;
  } else {
    edge.T_from_to = data.agent_local_pose(prev.id).between(data.agent_local_pose(kf.id));
    edge.information = diag_information(options.gap_sigma_xy_m_per_step * std::sqrt(double(steps)),
                                        options.gap_sigma_yaw_rad_per_step * std::sqrt(double(steps)));
  }
  return edge;
}

}  // namespace cairn::base
