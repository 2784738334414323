// RobotLinker: links on identified landmarks (markers; see robot_linker.h and landmarks.h) and on
// robots seeing robots (sightings.h: each sighting is a point known in both robots' frames).
// - Every robot keeps its own estimate of each landmark it saw, in its local frame
//   (MapperData::local_landmarks, filled by note_keyframe).
// - Two robots not linked yet that saw the same landmarks: their frames are aligned on the shared
//   landmarks (Umeyama, outliers dropped while the residual is above a gate) and the hypothesis goes
//   through the same map-level consistency check as scan closures (judge_link). A map that refutes
//   it rejects it; a map that confirms it links with min_link_landmarks_map_confirmed landmarks; an
//   inconclusive map (featureless or not-yet-overlapping scans) needs min_link_landmarks.
// - Once robots are linked, each landmark is a 2D point node of the pose graph (the mapper's part).
#include "base_station/core/landmarks.h"
#include "base_station/core/robot_linker.h"
#include "base_station/core/sightings.h"

#include <set>

namespace cairn::base {

void RobotLinker::link_by_landmarks(MapperData* data, LinkUpdate* update) {
  if (!options_.landmarks.enabled) return;
  for (auto a = data->local_landmarks.begin(); a != data->local_landmarks.end(); ++a) {
    for (auto b = std::next(a); b != data->local_landmarks.end(); ++b) {
      if (component_of(*data, a->first) == component_of(*data, b->first)) continue;  // linked (maybe just now)
      try_link_by_landmarks(data, a->first, b->first, update);
    }
  }
}

bool RobotLinker::try_link_by_landmarks(MapperData* data, RobotId ra, RobotId rb, LinkUpdate* update) {
  const LandmarkOptions& o = options_.landmarks;
  const LocalLandmarks& la = data->local_landmarks.at(ra);
  const LocalLandmarks& lb = data->local_landmarks.at(rb);
  if (shared_landmarks(la, lb) < std::min(o.min_link_landmarks, o.min_link_landmarks_map_confirmed)) return false;
  const int observations = landmark_observations_[ra] + landmark_observations_[rb];
  if (!due_for_judging(&landmark_pair_judged_at_, {ra, rb}, observations)) return false;
  return try_link_on_points(data, ra, rb, la, lb, "markers", update);
}

void RobotLinker::link_by_sightings(MapperData* data, LinkUpdate* update) {
  if (!options_.landmarks.enabled) return;
  std::set<std::pair<RobotId, RobotId>> pairs;
  for (const Sighting& s : data->sightings) {
    pairs.insert({std::min(s.observer.robot, s.seen), std::max(s.observer.robot, s.seen)});
  }
  for (const auto& [ra, rb] : pairs) {
    if (component_of(*data, ra) == component_of(*data, rb)) continue;  // linked (maybe just now)
    const int observations = sighting_counts_[ra] + sighting_counts_[rb];
    if (!due_for_judging(&sighting_pair_judged_at_, {ra, rb}, observations)) continue;
    LocalLandmarks la, lb;
    sighting_correspondences(*data, ra, rb, &la, &lb);
    try_link_on_points(data, ra, rb, la, lb, "sightings", update);
  }
}

bool RobotLinker::due_for_judging(std::map<std::pair<RobotId, RobotId>, int>* judged_at,
                                  std::pair<RobotId, RobotId> pair, int observations) const {
  auto judged = judged_at->find(pair);
  if (judged != judged_at->end() && observations - judged->second < options_.landmarks.retry_observations) {
    return false;
  }
  (*judged_at)[pair] = observations;
  return true;
}

bool RobotLinker::try_link_on_points(MapperData* data, RobotId ra, RobotId rb, const LocalLandmarks& la,
                                     const LocalLandmarks& lb, const std::string& kind, LinkUpdate* update) {
  const LandmarkOptions& o = options_.landmarks;
  const int needed = std::min(o.min_link_landmarks, o.min_link_landmarks_map_confirmed);
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
    ev.reason = kind + ": " + al.reason;
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
    const SE2 T_a_b = data->keyframe(ka).T_local_base.inverse() * al.T_a_b * data->keyframe(kb).T_local_base;
    closures.push_back(LoopClosure{ka, kb, T_a_b, covariance, 1.0});
  }
  LinkEvent map = judge_link(*data, ra, rb, closures);
  ev.contradiction_ratio = map.contradiction_ratio;
  const int n = int(al.used.size());
  const std::string what = std::to_string(n) + " shared " + kind + " (rms " + format_number("%.2f", al.rms_m) + " m, " +
                           std::to_string(al.dropped.size()) + " dropped)";
  if (!map.accepted && !map.inconclusive) {
    ev.reason = kind + ": " + what + " refuted by the map: " + map.reason;
    ++stats_.rejected_map_contradiction;
    record(ev);
    return false;
  }
  if (map.inconclusive && n < o.min_link_landmarks) {
    ev.inconclusive = true;
    ev.reason = kind + ": " + what + ", map check inconclusive (" + map.reason +
                "): " + std::to_string(o.min_link_landmarks) + " needed without map evidence";
    record(ev);
    return false;
  }
  ++stats_.hypotheses;
  ++stats_.linked;
  ev.accepted = true;
  ev.robot = data->linked(ra) || !data->linked(rb) ? rb : ra;
  ev.other = ev.robot == rb ? ra : rb;
  ev.reason = "linked via " + what + (map.accepted ? ", map consistent" : ", map inconclusive");
  record(ev);
  data->loops.push_back(closures.front());  // places the robot (place_new_robots); landmarks do the rest
  data->loops.insert(data->loops.end(), map.guided.begin(), map.guided.end());  // as in try_link_pair
  join_components(*data, ra, rb);
  update->full_resolve = true;
  return true;
}

}  // namespace cairn::base
