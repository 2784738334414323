// MultiRobotMapper: identified landmarks (markers) in keyframes (see multi_robot_mapper.h and
// landmarks.h).
// - Every robot keeps its own estimate of each landmark it saw, in its local frame.
// - Two robots not linked yet that saw the same landmarks: their frames are aligned on the shared
//   landmarks (Umeyama, outliers dropped while the residual is above a gate) and the hypothesis goes
//   through the same map-level consistency check as scan closures (judge_link). A map that refutes
//   it rejects it; a map that confirms it links with min_link_landmarks_map_confirmed landmarks; an
//   inconclusive map (featureless or not-yet-overlapping scans) needs min_link_landmarks.
// - Once robots are linked, each landmark is a 2D point node of the pose graph with a range-bearing
//   residual (robust loss) per observation, so a landmark seen by two robots (or twice by one)
//   constrains their keyframes.
#include "base_station/core/landmarks.h"
#include "base_station/core/multi_robot_mapper.h"

namespace cairn::base {

void MultiRobotMapper::note_landmarks(const Keyframe& kf) {
  const LandmarkOptions& o = options_.landmarks;
  if (!o.enabled || kf.landmarks.empty()) return;
  const RobotId robot = kf.id.robot;
  const int used = accumulate_landmarks(kf, o.min_range_m, &local_landmarks_[robot], nullptr);
  if (used == 0) return;
  landmark_observations_[robot] += used;
  std::vector<RobotId> others;
  for (const auto& [other, list] : local_landmarks_) {
    if (other != robot && component_of(other) != component_of(robot)) others.push_back(other);
  }
  for (RobotId other : others) {
    if (component_of(other) == component_of(robot)) continue;  // linked by the previous one
    try_link_by_landmarks(std::min(robot, other), std::max(robot, other));
  }
}

bool MultiRobotMapper::try_link_by_landmarks(RobotId ra, RobotId rb) {
  const LandmarkOptions& o = options_.landmarks;
  const LocalLandmarks& la = local_landmarks_.at(ra);
  const LocalLandmarks& lb = local_landmarks_.at(rb);
  const int needed = std::min(o.min_link_landmarks, o.min_link_landmarks_map_confirmed);
  if (shared_landmarks(la, lb) < needed) return false;
  const std::pair<RobotId, RobotId> key{ra, rb};
  const int observations = landmark_observations_[ra] + landmark_observations_[rb];
  auto judged = landmark_pair_judged_at_.find(key);
  if (judged != landmark_pair_judged_at_.end() && observations - judged->second < o.retry_observations) return false;
  landmark_pair_judged_at_[key] = observations;

  const LandmarkAlignment al = align_landmarks(la, lb, needed, o.max_link_rms_m, o.min_link_spread_m);
  LinkEvent ev{rb, ra, int(al.used.size()), false, false, 0.0, {}};
  auto record = [&](LinkEvent e) {
    if (!e.accepted && !landmark_link_events_.empty() && landmark_link_events_.back().robot == e.robot &&
        landmark_link_events_.back().other == e.other && !landmark_link_events_.back().accepted) {
      landmark_link_events_.back() = e;  // keep only the latest refusal per pair in a row
    } else {
      landmark_link_events_.push_back(e);
    }
  };
  if (!al.ok) {
    ev.reason = "markers: " + al.reason;
    record(ev);
    return false;
  }
  // One closure per shared landmark, between the keyframes that saw it closest (all carry al.T_a_b).
  Covariance3 covariance = Covariance3::Zero();
  covariance.diagonal() << o.link_sigma_xy_m * o.link_sigma_xy_m, o.link_sigma_xy_m * o.link_sigma_xy_m,
      o.link_sigma_yaw_rad * o.link_sigma_yaw_rad;
  std::vector<LoopClosure> closures;
  for (LandmarkId id : al.used) {
    const KeyframeId ka = la.at(id).nearest, kb = lb.at(id).nearest;
    const SE2 T_a_b = keyframes_.at(ka).T_local_base.inverse() * al.T_a_b * keyframes_.at(kb).T_local_base;
    closures.push_back(LoopClosure{ka, kb, T_a_b, covariance, 1.0});
  }
  LinkEvent map = judge_link(ra, rb, closures);
  ev.contradiction_ratio = map.contradiction_ratio;
  const int n = int(al.used.size());
  const std::string what = std::to_string(n) + " shared markers (rms " + format_number("%.2f", al.rms_m) + " m, " +
                           std::to_string(al.dropped.size()) + " dropped)";
  if (!map.accepted && !map.inconclusive) {
    ev.reason = "markers: " + what + " refuted by the map: " + map.reason;
    ++link_stats_.rejected_map_contradiction;
    record(ev);
    return false;
  }
  if (map.inconclusive && n < o.min_link_landmarks) {
    ev.inconclusive = true;
    ev.reason = "markers: " + what + ", map check inconclusive (" + map.reason +
                "): " + std::to_string(o.min_link_landmarks) + " markers needed without map evidence";
    record(ev);
    return false;
  }
  ++link_stats_.hypotheses;
  ++link_stats_.linked;
  ev.accepted = true;
  ev.robot = linked(ra) || !linked(rb) ? rb : ra;
  ev.other = ev.robot == rb ? ra : rb;
  ev.reason = "linked via " + what + (map.accepted ? ", map consistent" : ", map inconclusive");
  record(ev);
  loops_.push_back(closures.front());  // places the robot (place_new_robots); landmarks do the rest
  loops_.insert(loops_.end(), map.guided.begin(), map.guided.end());  // as in try_link_pair
  const RobotId ca = component_of(ra), cb = component_of(rb);
  if (anchor_ && component_of(*anchor_) == cb) {  // the anchor's component keeps its root
    component_parent_[ca] = cb;
  } else {
    component_parent_[cb] = ca;
  }
  full_resolve_ = true;
  return true;
}

void MultiRobotMapper::add_landmark_edges(RobotId robot) {
  const LandmarkOptions& o = options_.landmarks;
  if (!o.enabled) return;
  for (auto it = keyframes_.lower_bound(KeyframeId{robot, 0}); it != keyframes_.end() && it->first.robot == robot;
       ++it) {
    const Keyframe& kf = it->second;
    if (kf.landmarks.empty() || !graph_.has_node(kf.id) || graph_.has_landmark_edges_from(kf.id)) continue;
    for (const LandmarkObservation& l : kf.landmarks) {
      if (!validate_landmark_observation(l).empty() || l.range_m < o.min_range_m) continue;
      graph_.add_landmark_edge(LandmarkEdge{kf.id, l.id, l.range_m, l.bearing_rad, o.sigma_scale * l.sigma_range_m,
                                            o.sigma_scale * l.sigma_bearing_rad});
    }
  }
}

}  // namespace cairn::base
