// AgentPipeline: identified landmark (marker) observations carried into keyframes (see
// agent_pipeline.h). An observation made at time t from the base pose P(t) (local SLAM, interpolated
// between processed scans) goes into the first keyframe K emitted with a stamp >= t, re-expressed
// from K's base frame: point K^-1 P(t) p, with its range/bearing sigmas propagated
// (common/landmark_observation.h reexpress_landmark).
// The other robots' markers seen by the camera (common/robot_markers.h) become landmark observations
// with their robot's reserved id, not object reports: they move, the base pairs them with the seen
// robot's own pose at that time.
#include "common/robot_markers.h"
#include "robot_agent/core/agent_pipeline.h"

namespace cairn::agent {

void AgentPipeline::add_landmark(const LandmarkObservation& observation) {
  ++stats_.landmarks_received;
  if (!validate_landmark_observation(observation).empty()) {
    ++stats_.landmarks_invalid;
    return;
  }
  // Keep the buffer in stamp order (observations of one sensor arrive in order; others may not).
  auto it = landmarks_.end();
  while (it != landmarks_.begin() && std::prev(it)->stamp_ns > observation.stamp_ns) --it;
  landmarks_.insert(it, observation);
}

std::vector<Detection> AgentPipeline::take_robot_sightings(StampNs stamp_ns, std::vector<Detection>* detections) {
  std::vector<Detection> objects;
  for (Detection& d : *detections) {
    const std::optional<RobotId> seen = robot_of_marker_class(d.class_name);
    if (!seen) {
      objects.push_back(std::move(d));
      continue;
    }
    // A marker cut by the image border or without depth has no reliable centre.
    if (*seen == robot_ || !d.has_depth || d.truncated_side) continue;
    LandmarkObservation o;
    o.id = robot_marker_landmark(*seen);
    o.stamp_ns = stamp_ns;
    o.range_m = d.centroid_base.head<2>().norm();
    o.bearing_rad = std::atan2(d.centroid_base.y(), d.centroid_base.x());
    o.sigma_range_m = options_.sighting_sigma_range_m + options_.sighting_sigma_range_per_m * o.range_m;
    o.sigma_bearing_rad = options_.sighting_sigma_bearing_rad;
    ++stats_.robot_sightings;
    add_landmark(o);
  }
  return objects;
}

void AgentPipeline::attach_landmarks(Keyframe* kf) {
  const SE2 T_kf_local = kf->T_local_base.inverse();
  while (!landmarks_.empty() && landmarks_.front().stamp_ns <= kf->stamp_ns) {
    const LandmarkObservation& o = landmarks_.front();
    kf->landmarks.push_back(reexpress_landmark(o, T_kf_local * pose_at(o.stamp_ns)));
    ++stats_.landmarks_in_keyframes;
    landmarks_.pop_front();
  }
}

}  // namespace cairn::agent
