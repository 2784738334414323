#include "robot_agent/core/agent_pipeline.h"

#include <algorithm>
#include <limits>

#include "common/scan_context.h"

namespace cairn::agent {

LaserScan without_teammates(const LaserScan& scan, float min_intensity, int* dropped) {
  LaserScan out = scan;
  for (size_t i = 0; i < out.ranges_m.size(); ++i) {
    if (on_teammate(scan, i, min_intensity)) {
      out.ranges_m[i] = std::numeric_limits<float>::infinity();  // as if no return
      ++*dropped;
    }
  }
  return out;
}

AgentPipeline::AgentPipeline(RobotId robot, const AgentOptions& options)
    : robot_(robot),
      options_(options),
      local_slam_(options.local_slam),
      keyframer_(robot, options.keyframer),
      detector_(options.detector),
      tracker_(robot, options.tracker),
      optical_flow_(options.optical_flow),
      saliency_pool_(options.saliency_map),
      dead_reckoning_(options.dead_reckoning) {}

void AgentPipeline::add_odometry(const OdometryReading& odometry) {
  ++stats_.odometry_received;
  if (!options_.use_odometry) return;
  if (!odometry_.empty() && odometry.stamp_ns < odometry_.back().stamp_ns) return;  // out of order
  if (first_odometry_ns_ < 0) first_odometry_ns_ = odometry.stamp_ns;
  odometry_.push_back(odometry);
}

void AgentPipeline::add_scan(const LaserScan& scan) {
  ++stats_.scans_received;
  const StampNs newest = scans_.empty() ? last_scan_stamp_ns_ : scans_.back().stamp_ns;
  if ((any_scan_processed_ || !scans_.empty()) && scan.stamp_ns < newest) {
    ++stats_.scans_out_of_order;
    return;
  }
  scans_.push_back(scan);
}

void AgentPipeline::add_rgbd(const RgbdFrame& frame) {
  ++stats_.rgbd_received;
  if (!options_.enable_objects) return;
  if (!frame.valid()) {
    ++stats_.rgbd_invalid;
    return;
  }
  frames_.push_back(frame);
}

bool AgentPipeline::scan_ready(bool flush) const {
  if (scans_.empty()) return false;
  if (flush || !options_.use_odometry) return true;
  if (!odometry_.empty() && odometry_.back().stamp_ns >= scans_.front().stamp_ns) return true;
  return int(scans_.size()) > options_.max_pending_scans;
}

bool AgentPipeline::rgbd_ready(bool flush) const {
  if (frames_.empty()) return false;
  // Canonical order: a frame right after the first scan with a stamp >= its own.
  if (any_scan_processed_ && last_scan_stamp_ns_ >= frames_.front().stamp_ns) return true;
  return flush && scans_.empty();
}

std::optional<SE2> AgentPipeline::odometry_at(StampNs t) const {
  if (!options_.use_odometry || odometry_.empty()) return std::nullopt;
  const auto after = std::lower_bound(odometry_.begin(), odometry_.end(), t,
                                      [](const OdometryReading& o, StampNs s) { return o.stamp_ns < s; });
  if (after == odometry_.end()) return odometry_.back().T_odom_base;  // hold the last reading
  if (after == odometry_.begin() || after->stamp_ns == t) return after->T_odom_base;
  const auto before = std::prev(after);
  const double s = double(t - before->stamp_ns) / double(after->stamp_ns - before->stamp_ns);
  return SE2::interpolate(before->T_odom_base, after->T_odom_base, s);
}

Anchor AgentPipeline::anchor_at(StampNs t) const {
  const auto it = std::upper_bound(anchor_stamps_ns_.begin(), anchor_stamps_ns_.end(), t);
  if (it == anchor_stamps_ns_.begin()) return Anchor{};
  return anchors_[size_t(std::distance(anchor_stamps_ns_.begin(), it) - 1)];
}

void AgentPipeline::process_scan(AgentOutputs* out) {
  const LaserScan scan = std::move(scans_.front());
  scans_.pop_front();
  // Teammates move: matched against, they drag the scan with them (a convoy in a corridor slid
  // 0.2-1.2 m per keyframe on the 64 m site). Their reflector beams are left out of SLAM and the
  // keyframes; navigation still gets the whole scan (it must not drive into them).
  const LaserScan slam_scan = without_teammates(scan, options_.teammate_min_intensity, &stats_.teammate_beams);
  if (options_.use_odometry && (odometry_.empty() || odometry_.back().stamp_ns < scan.stamp_ns)) {
    ++stats_.scans_without_odometry;
  }
  if (laser_lost_) {
    laser_lost_ = false;  // back: the local SLAM goes on from its last pose and the odometry since
    ++stats_.laser_recoveries;
  }
  const LocalSlamResult r = local_slam_.add_scan(slam_scan, odometry_at(scan.stamp_ns));
  any_scan_processed_ = true;
  last_scan_stamp_ns_ = scan.stamp_ns;
  // Drop odometry no longer needed for interpolation (keep the last reading <= this scan).
  while (odometry_.size() > 1 && odometry_[1].stamp_ns <= scan.stamp_ns) odometry_.pop_front();
  stats_.beams += r.filter_stats;
  using S = LocalSlamResult::Status;
  switch (r.status) {
    case S::kFirstScan:
    case S::kMatched:
      ++stats_.scans_matched;
      break;
    case S::kMotionFiltered:
      ++stats_.scans_motion_filtered;
      break;
    case S::kTooFewPoints:
      ++stats_.scans_too_few_points;
      break;
    case S::kMatchFailed:
      ++stats_.scans_match_failed;
      break;
    case S::kOdometryStalled:
      ++stats_.scans_odometry_stalled;
      break;
  }
  if (r.status != S::kTooFewPoints || !tracked_.empty()) {
    tracked_.push_back({scan.stamp_ns, r.pose});
    out->scans.push_back({scan, r.pose});
  }
  if (!r.matched()) return;
  trajectory_.push_back({scan.stamp_ns, r.pose});
  if (auto kf = keyframer_.add(slam_scan, r.pose, r.covariance)) emit_keyframe(std::move(*kf), out);
}

void AgentPipeline::emit_keyframe(Keyframe kf, AgentOutputs* out) {
  attach_landmarks(&kf);  // agent_pipeline_landmarks.cpp
  kf.salient = saliency_pool_.take(kf.T_local_base);
  stats_.salient_points += int(kf.salient.size());
  if (!kf.scan.ranges_m.empty()) {
    // Place descriptor for the base's place recognition (common/scan_context.h, default options on
    // both sides), from this keyframe and the last descriptor_keyframes - 1 ones with scans.
    const ScanContextOptions scan_context;
    std::vector<const Keyframe*> recent;
    for (const Keyframe& k : recent_keyframes_) recent.push_back(&k);
    kf.place_descriptor = compute_keyframe_scan_context(kf, recent, scan_context);
    recent_keyframes_.push_back(kf);
    recent_keyframes_.back().place_descriptor.clear();
    recent_keyframes_.back().salient.clear();
    while (int(recent_keyframes_.size()) > scan_context.descriptor_keyframes - 1) recent_keyframes_.pop_front();
  }
  anchors_.push_back(Anchor{kf.id.seq, kf.T_local_base});
  anchor_stamps_ns_.push_back(kf.stamp_ns);
  out->keyframes.push_back(std::move(kf));
  ++stats_.keyframes;
}

void AgentPipeline::process_rgbd(AgentOutputs* out) {
  const RgbdFrame frame = std::move(frames_.front());
  frames_.pop_front();
  ++stats_.rgbd_processed;
  DetectionFrame analysed = detector_.analyse(frame);
  const std::vector<Detection> detections = take_robot_sightings(frame.stamp_ns, &analysed.detections);
  if (options_.enable_saliency_map)
    saliency_pool_.add(pose_at(frame.stamp_ns), project_saliency(frame, analysed.saliency, options_.saliency_map));
  stats_.detections += int(detections.size());
  std::vector<ObjectReport> reports =
      tracker_.update(frame.stamp_ns, detections, pose_at(frame.stamp_ns), anchor_at(frame.stamp_ns));
  stats_.object_reports += int(reports.size());
  // Collision risk from optical flow; speed and yaw rate from the tracked poses over 0.2 s.
  const StampNs back_ns = 200'000'000;
  const SE2 d = pose_at(frame.stamp_ns - back_ns).inverse() * pose_at(frame.stamp_ns);
  const CollisionEstimate c = optical_flow_.update(frame, d.translation().norm() / 0.2, d.yaw() / 0.2);
  stats_.collision_risk = c.collision_risk;
  stats_.collision_estimates += c.converged;
  for (ObjectReport& r : reports) out->objects.push_back(std::move(r));
}

AgentOutputs AgentPipeline::process(bool flush) {
  AgentOutputs out;
  while (true) {
    if (rgbd_ready(flush)) {
      process_rgbd(&out);
    } else if (scan_ready(flush)) {
      process_scan(&out);
    } else if (dead_reckoning_ready()) {
      dead_reckoning_step(&out);  // agent_pipeline_dead_reckoning.cpp
    } else {
      break;
    }
  }
  out.keyframe_poses = keyframe_poses(flush);
  return out;
}

std::optional<KeyframePoses> AgentPipeline::keyframe_poses(bool flush) {
  if (flush && any_scan_processed_ && finished_ns_ != last_scan_stamp_ns_) {  // the final optimisation, once
    local_slam_.finish();
    finished_ns_ = last_scan_stamp_ns_;
  }
  const int optimizations = local_slam_.loop_closure().stats().optimizations;
  if (optimizations == optimizations_sent_ || anchor_stamps_ns_.empty()) return std::nullopt;
  const StampNs interval_ns = StampNs(options_.keyframe_poses_min_interval_s * 1e9);
  if (!flush && poses_sent_ns_ && last_scan_stamp_ns_ - *poses_sent_ns_ < interval_ns) return std::nullopt;
  // Keyframe stamps are scan stamps: one merge pass over the optimised trajectory (stamp order).
  const Trajectory optimized = local_slam_.optimized_trajectory();
  KeyframePoses update{robot_, last_scan_stamp_ns_, {}};
  auto it = optimized.begin();
  for (size_t i = 0; i < anchors_.size(); ++i) {
    while (it != optimized.end() && it->stamp_ns < anchor_stamps_ns_[i]) ++it;
    if (it == optimized.end() || it->stamp_ns != anchor_stamps_ns_[i]) continue;
    update.poses.push_back(KeyframePose{anchors_[i].seq, it->pose});
  }
  optimizations_sent_ = optimizations;
  poses_sent_ns_ = last_scan_stamp_ns_;
  ++stats_.keyframe_pose_updates;
  return update;
}

SE2 AgentPipeline::pose_at(StampNs t) const {
  if (tracked_.empty()) return SE2();
  if (t <= tracked_.front().stamp_ns) return tracked_.front().pose;
  if (t >= tracked_.back().stamp_ns) return tracked_.back().pose;
  const auto p = interpolate_pose(tracked_, t, std::numeric_limits<StampNs>::max());
  return p ? *p : tracked_.back().pose;
}

AgentStats AgentPipeline::stats() const {
  AgentStats s = stats_;
  s.object_tracks = int(tracker_.num_tracks());
  s.object_tracks_confirmed = int(tracker_.num_confirmed());
  s.submaps_finished = int(local_slam_.submaps().finished().size());
  s.loop_closures = local_slam_.loop_closure().stats().loop_closures;
  s.pose_graph_optimizations = local_slam_.loop_closure().stats().optimizations;
  return s;
}

}  // namespace cairn::agent
