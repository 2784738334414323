// AgentPipeline: a robot whose laser is silent (see agent_pipeline.h, AgentOptions::
// dead_reckon_without_laser). Once odometry has gone on for dead_reckoning.laser_timeout_s past the
// newest processed scan (or, without any scan, past the first odometry reading), a pose from odometry
// alone is made every step_interval_s from where the laser last placed the robot (DeadReckoning).
// Each is a PosedScan without beams (navigation steers by it on the map it has), RGB-D frames and
// landmarks are placed by it, and keyframes are cut from it (Keyframer::add_dead_reckoned) with the
// odometry's grown covariance: the base still gets the robot's trajectory, landmarks and finds. The
// first scan that comes back ends it (process_scan): the local SLAM goes on from its own last pose
// and the odometry since, the same prediction the dead reckoning made.
#include "robot_agent/core/agent_pipeline.h"

namespace cairn::agent {
namespace {

StampNs to_ns(double s) { return StampNs(s * 1e9); }

}  // namespace

bool AgentPipeline::dead_reckoning_ready() const {
  if (!options_.dead_reckon_without_laser || !options_.use_odometry || odometry_.empty() || !scans_.empty()) {
    return false;
  }
  const StampNs newest_ns = odometry_.back().stamp_ns;
  if (laser_lost_) return next_dead_reckoning_ns_ <= newest_ns;
  if (!any_scan_processed_ && !stamps_may_judge_laser_) return false;  // the first scan may only be late
  const StampNs silent_since_ns = any_scan_processed_ ? last_scan_stamp_ns_ : first_odometry_ns_;
  return newest_ns - silent_since_ns >= to_ns(dead_reckoning_.options().laser_timeout_s);
}

void AgentPipeline::dead_reckoning_step(AgentOutputs* out) {
  const StampNs step_ns = std::max<StampNs>(1, to_ns(dead_reckoning_.options().step_interval_s));
  if (!laser_lost_) {
    laser_lost_ = true;
    ++stats_.laser_losses;
    const StampNs since_ns = any_scan_processed_ ? last_scan_stamp_ns_ : first_odometry_ns_;
    dead_reckoning_.start(tracked_.empty() ? SE2() : tracked_.back().pose, *odometry_at(since_ns));
    next_dead_reckoning_ns_ = since_ns + step_ns;
  }
  const StampNs t_ns = next_dead_reckoning_ns_;
  next_dead_reckoning_ns_ += step_ns;
  const SE2 pose = dead_reckoning_.advance(*odometry_at(t_ns));
  ++stats_.dead_reckoned_poses;
  LaserScan no_beams;
  no_beams.stamp_ns = t_ns;
  tracked_.push_back({t_ns, pose});
  out->scans.push_back({no_beams, pose});
  any_scan_processed_ = true;
  last_scan_stamp_ns_ = t_ns;
  // Keep the last odometry reading <= this stamp for the next increment.
  while (odometry_.size() > 1 && odometry_[1].stamp_ns <= t_ns) odometry_.pop_front();
  if (auto kf = keyframer_.add_dead_reckoned(t_ns, pose, dead_reckoning_.covariance_since_keyframe())) {
    dead_reckoning_.keyframe_emitted();
    ++stats_.keyframes_without_scan;
    emit_keyframe(std::move(*kf), out);
  }
}

}  // namespace cairn::agent
