// BaseNode, what the console sees: each robot's link, the snapshot the console serves (rebuilt every
// optimise tick and at once after an operator's verdict), and when the keyframes it shows arrived.
#include <chrono>
#include <cmath>

#include "base_station/app/base_node.h"

namespace cairn::base {

using Clock = std::chrono::steady_clock;

void BaseNode::note_keyframe_arrival() {
  if (unshown_keyframe_wall_s_ > 0) return;  // the oldest not yet shown counts
  unshown_keyframe_wall_s_ = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

nlohmann::json BaseNode::link_stats() const {
  nlohmann::json links = nlohmann::json::object();
  for (const auto& [robot, link] : links_) {
    nlohmann::json j;
    j["bytes_sent"] = link.has_status ? link.last_status.bytes_sent() : 0;
    j["keyframe_bytes"] = link.has_status ? link.last_status.keyframe_bytes() : 0;
    j["object_bytes"] = link.has_status ? link.last_status.object_bytes() : 0;
    j["object_messages"] = link.has_status ? link.last_status.object_messages() : 0;
    j["keyframes_sent"] = link.has_status ? link.last_status.keyframes_sent() : 0;
    j["objects_sent"] = link.has_status ? link.last_status.objects_sent() : 0;
    j["scans_processed"] = link.has_status ? link.last_status.scans_processed() : 0;
    j["finished"] = link.has_status && link.last_status.finished();
    const bool battery_known = link.has_status && link.last_status.battery_pct() >= 0.f;  // negative: not known
    j["battery_pct"] = battery_known ? nlohmann::json(link.last_status.battery_pct()) : nlohmann::json();
    j["collision_risk"] = link.has_status && link.last_status.collision_risk();  // the robot's optical flow
    j["laser_lost"] = link.has_status && link.last_status.laser_lost();
    const double age_s = link.last_heard_s < 0 ? -1.0 : now_s() - link.last_heard_s;
    j["last_heard_age_s"] = age_s;
    // What the console shows: the link's state and the bytes received from the robot.
    j["label"] = sessions_.label(robot);
    j["state"] = !sessions_.is_current(robot)  ? "restarted"  // this session ended; the robot runs a newer one
                 : !link.has_status            ? "unknown"
                 : link.last_status.finished() ? "finished"
                 : age_s < 0.0                 ? "lost"  // known from the journal only
                 : age_s < 2.0                 ? "ok"
                 : age_s < 10.0                ? "stale"
                                               : "lost";
    j["bytes_rx"] = link.has_status ? link.last_status.bytes_sent() : 0;
    j["bad_samples"] = link.bad_samples;
    j["keyframe_pose_updates"] = link.keyframe_pose_updates;
    if (const auto rtt_ms = link.round_trip.median_ms()) j["rtt_ms"] = std::lround(*rtt_ms);
    add_navigation_json(robot, &j);
    links[std::to_string(robot.value)] = j;
  }
  return links;
}

void BaseNode::refresh_snapshot(bool full) {
  last_snapshot_ = Clock::now();
  const MergedMap merged = judged_map();
  SnapshotOptions options;
  options.render_images = full;
  ConsoleSnapshot snapshot = make_snapshot(merged, link_stats(), options, &plan_);
  if (!full) {  // the images of the last full snapshot
    const std::shared_ptr<const ConsoleSnapshot> last = latest_snapshot_.get();
    snapshot.map_png = last->map_png;
    snapshot.own_maps = last->own_maps;
    snapshot.layers["own_frames"] = last->layers.value("own_frames", nlohmann::json::object());
  }
  snapshot.command_context = command_context(merged);
  for (const BlacklistedGoal& g : goals_.blacklisted())  // the map view's "could not reach" layer
    snapshot.layers["unreachable"].push_back(
        {{"x_m", g.position_m.x()}, {"y_m", g.position_m.y()}, {"robot", g.robot.value}, {"why", to_string(g.why)}});
  const double wall_s = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  snapshot.status["alerts"] = alert_log_.observe(snapshot.status["alerts"], wall_s, inbox_.acked_alerts());
  snapshot.alert_log = alert_log_.log();
  // For the page's update latency: when the oldest keyframe this snapshot shows first reached us.
  snapshot.status["keyframe_wall_s"] =
      unshown_keyframe_wall_s_ > 0 ? nlohmann::json(unshown_keyframe_wall_s_) : nlohmann::json();
  unshown_keyframe_wall_s_ = -1.0;
  latest_snapshot_.publish(std::move(snapshot));
}

}  // namespace cairn::base

namespace cairn::base {

void BaseNode::publish_ros2() {
  if (!ros2_out_) return;
  std::map<RobotId, SE2> poses;  // each robot's newest reported pose, in its own frame
  for (const auto& [robot, link] : links_) {
    if (!link.has_status) continue;
    const auto& p = link.last_status.pose();
    if (std::isfinite(p.x_m()) && std::isfinite(p.y_m()) && std::isfinite(p.yaw_rad())) {
      poses[robot] = SE2(p.x_m(), p.y_m(), p.yaw_rad());
    }
  }
  // Stamped with the wall clock, as ROS tools expect of live data (the paths keep mission stamps).
  ros2_out_->publish(judged_map(), poses, dds::reception_clock_ns());
}

}  // namespace cairn::base
