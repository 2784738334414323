// AgentPipeline: identified landmark (marker) observations carried into keyframes (see
// agent_pipeline.h). An observation made at time t from the base pose P(t) (local SLAM, interpolated
// between processed scans) goes into the first keyframe K emitted with a stamp >= t, re-expressed
// from K's base frame: point K^-1 P(t) p, with its range/bearing sigmas propagated
// (common/landmark_observation.h reexpress_landmark).
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
