#include "robot_agent/app/agent_node.h"

#include <chrono>
#include <cmath>
#include <random>
#include <thread>

#include "dds/conversions.h"
#include "dds/navigation_conversions.h"

namespace cairn::agent {

using Clock = std::chrono::steady_clock;

namespace {

NavigatorOptions with_teammate_threshold(NavigatorOptions navigator, const AgentOptions& core) {
  navigator.map.teammate_min_intensity = core.teammate_min_intensity;  // one threshold for SLAM and navigation
  return navigator;
}

}  // namespace

AgentNode::AgentNode(RobotId robot, const AgentOptions& core_options, const AgentNodeOptions& options)
    : robot_(robot),
      options_(options),
      pipeline_(robot, core_options),
      log_(make_logger("agent", robot)),
      navigator_(with_teammate_threshold(options.navigator, core_options)),
      behaviour_(options.behaviour),
      own_options_(options.own_exploration) {
  keyframe_window_ =
      SendWindow<cairn_msgs::Keyframe>(options.link_budget_bytes_per_sec > 0 ? options.keyframes_in_flight : 0);
}

std::unique_ptr<AgentNode> AgentNode::create(RobotId robot, const AgentOptions& core_options,
                                             const AgentNodeOptions& options, const SensorInput& input,
                                             std::string* error) {
  std::unique_ptr<AgentNode> n(new AgentNode(robot, core_options, options));
  std::random_device entropy;  // a new session per start, unrelated to the last one's
  while (n->session_ == 0) n->session_ = options.session != 0 ? options.session : uint32_t(entropy());
  if (input.log) {
    if (input.log->scans.empty()) {
      *error = "the log holds no laser scans";
      return nullptr;
    }
    n->log_source_ = std::make_unique<LogSource>(*input.log, input.log_options);
  }
  if (input.robot_log) {
    // A robot without laser is replayed from its odometry alone (AgentOptions::dead_reckon_without_laser).
    const bool dead_reckons = core_options.dead_reckon_without_laser && core_options.use_odometry;
    if (input.robot_log->scans.empty() && (input.robot_log->odometry.empty() || !dead_reckons)) {
      *error = "the multi-robot log holds no laser scans for " + to_string(robot) +
               (input.robot_log->odometry.empty() ? " and no odometry" : " (and dead reckoning is off)");
      return nullptr;
    }
    n->log_source_ = std::make_unique<LogSource>(*input.robot_log, input.log_options);
  }
  dds::ParticipantOptions po;
  po.domain_id = options.domain_id;
  po.name = "cairn_agent_" + std::to_string(robot.value);
  po.initial_peers = options.peers;
  po.security_dir = options.security_dir;
  po.link_budget_bytes_per_sec = options.link_budget_bytes_per_sec;
  if (options.link_budget_bytes_per_sec > 0) {  // a slow radio: announce less often
    po.announcement_period_s = dds::kSlowLinkAnnouncementPeriod_s;
    po.lease_duration_s = dds::kSlowLinkLeaseDuration_s;
  }
  if (!options.outbox_path.empty() && !n->open_outbox(error)) return nullptr;
  n->participant_ = dds::Participant::create(po, error);
  if (!n->participant_) return nullptr;
  auto& p = *n->participant_;
  n->odometry_in_ = std::make_unique<dds::Reader<dds::OdometryTopic>>(p, robot);
  n->laser_in_ = std::make_unique<dds::Reader<dds::LaserScanTopic>>(p, robot);
  n->rgbd_in_ = std::make_unique<dds::Reader<dds::RgbdTopic>>(p, robot);
  n->clock_in_ = std::make_unique<dds::Reader<dds::ClockTopic>>(p);
  n->ack_in_ = std::make_unique<dds::Reader<dds::AckTopic>>(p);
  n->goal_in_ = std::make_unique<dds::Reader<dds::GoalTopic>>(p);
  n->command_in_ = std::make_unique<dds::Reader<dds::OperatorCommandTopic>>(p);
  n->keep_out_in_ = std::make_unique<dds::Reader<dds::KeepOutTopic>>(p);
  if (options.ros2) {
    n->ros2_in_ = std::make_unique<Ros2SensorInput>(p, *options.ros2);
    if (!n->ros2_in_->ok()) {
      *error = "cannot create the agent's ROS 2 readers/writers";
      return nullptr;
    }
  }
  dds::QosOptions radio;
  radio.link_budgeted = options.link_budget_bytes_per_sec > 0;
  if (radio.link_budgeted) radio.heartbeat_period_s = dds::kSlowLinkHeartbeat_s;
  n->keyframe_out_ = std::make_unique<dds::Writer<dds::KeyframeTopic>>(p, radio);
  n->object_out_ = std::make_unique<dds::Writer<dds::ObjectTopic>>(p, radio);
  n->keyframe_poses_out_ = std::make_unique<dds::Writer<dds::KeyframePosesTopic>>(p, radio);
  // Statuses stay out of the budget: small, best effort and keep last 1, through the flow
  // controller's queue each one replaced the last before it went, and a robot's closing
  // "finished" statuses were lost with the process (the base waited for robot 3 for ever).
  dds::QosOptions status_qos;
  status_qos.heartbeat_period_s = radio.heartbeat_period_s;
  n->status_out_ = std::make_unique<dds::Writer<dds::StatusTopic>>(p, status_qos);
  n->cmd_out_ = std::make_unique<dds::Writer<dds::CmdVelTopic>>(p, robot);
  if (!n->cmd_out_->ok() || !n->odometry_in_->ok() || !n->laser_in_->ok() || !n->rgbd_in_->ok() ||
      !n->clock_in_->ok() || !n->ack_in_->ok() || !n->keyframe_out_->ok() || !n->object_out_->ok() ||
      !n->keyframe_poses_out_->ok() || !n->status_out_->ok() || !n->goal_in_->ok() || !n->command_in_->ok() ||
      !n->keep_out_in_->ok()) {
    *error = "cannot create the agent's DDS readers/writers";
    return nullptr;
  }
  return n;
}

bool AgentNode::poll_inputs() {
  bool any = false;
  std::string error;
  if (log_source_) {
    const double elapsed_s = std::chrono::duration<double>(Clock::now() - start_).count();
    any = log_source_->feed(elapsed_s, &pipeline_) > 0;
    input_finished_ = log_source_->finished();
  }
  if (ros2_in_) {
    any = ros2_in_->feed(&pipeline_, &error) > 0 || any;
    if (ros2_in_->refused() > ros2_refused_) {
      ros2_refused_ = ros2_in_->refused();
      CAIRN_LOG_EVERY_N_SEC(log_, spdlog::level::warn, 2.0, "refused a ROS 2 message ({} so far): {}", ros2_refused_,
                            error);
    }
    if (ros2_in_->ended() && !input_finished_) {
      log_->info("ROS 2 input ended: no scan for {:.1f} s", options_.ros2->idle_end_s);
      input_finished_ = true;
    }
  }
  auto reject = [&](const char* topic) {
    ++bad_samples_;
    CAIRN_LOG_EVERY_N_SEC(log_, spdlog::level::warn, 2.0, "dropped a bad {} sample: {}", topic, error);
  };
  for (const auto& m : odometry_in_->take_all()) {
    any = true;
    if (!first_odometry_arrival_) first_odometry_arrival_ = Clock::now();
    auto o = dds::check_robot(m.robot_id(), robot_, &error) ? dds::from_msg(m, &error) : std::nullopt;
    if (o)
      pipeline_.add_odometry(*o);
    else
      reject("odometry");
  }
  for (const auto& m : laser_in_->take_all()) {
    any = true;
    any_scan_arrived_ = true;
    auto s = dds::check_robot(m.robot_id(), robot_, &error) ? dds::from_msg(m, &error) : std::nullopt;
    if (s)
      pipeline_.add_scan(*s);
    else
      reject("laser_scan");
  }
  if (!log_source_ && !ros2_in_) {
    // Cairn's sensor topics: odometry stamps can run far ahead of a first scan that is only late.
    pipeline_.set_stamps_may_judge_laser(
        any_scan_arrived_ ||
        (first_odometry_arrival_ && std::chrono::duration<double>(Clock::now() - *first_odometry_arrival_).count() >=
                                        pipeline_.options().dead_reckoning.laser_timeout_s));
  }
  for (const auto& m : rgbd_in_->take_all()) {
    any = true;
    auto f = dds::check_robot(m.robot_id(), robot_, &error) ? dds::from_msg(m, &error) : std::nullopt;
    if (f)
      pipeline_.add_rgbd(*f);
    else
      reject("rgbd");
  }
  for (const auto& c : clock_in_->take_all()) {
    if (!log_source_) input_finished_ = input_finished_ || c.finished();
  }
  for (const auto& g : goal_in_->take_all()) {
    if (for_me(g)) take_goal(g);
  }
  for (const auto& c : command_in_->take_all()) {
    if (for_me(c)) take_command(c);  // a command to a session before a restart is not carried out
  }
  for (const auto& k : keep_out_in_->take_all()) {
    if (for_me(k)) take_keep_out(k);
  }
  for (const auto& [a, writer, received_ns] : ack_in_->take_all_from_writers()) {
    heard_any_ack_ = true;
    if (!for_me(a)) {  // another robot's, or an earlier session's this run resends from the outbox
      take_earlier_ack(a);
      continue;
    }
    heard_from_base();
    acked_keyframe_seq_ = std::max(acked_keyframe_seq_, a.keyframe_seq());
    acked_object_count_ = std::max(acked_object_count_, int(a.object_count()));
    note_own_ack();
    write_keyframes();                                            // room in flight
    if (a.probe_ns() != 0) probe_ = {a.probe_ns(), received_ns};  // echoed in the next status
  }
  return any;
}

void AgentNode::publish(const AgentOutputs& outputs) {
  OutgoingSamples samples;
  for (const auto& kf : outputs.keyframes) samples.keyframes.push_back(with_session(dds::to_msg(kf)));
  for (const auto& obj : outputs.objects) samples.objects.push_back(with_session(dds::to_msg(obj)));
  if (outputs.keyframe_poses) samples.keyframe_poses = with_session(dds::to_msg(*outputs.keyframe_poses));
  keep(samples);  // on disk first: a crash from here on loses nothing
  if (!own_session_may_speak()) {
    if (!samples.empty()) held_outputs_.push_back(std::move(samples));
    return;
  }
  for (const OutgoingSamples& held : held_outputs_) write_outputs(held);
  held_outputs_.clear();
  write_outputs(samples);
}

void AgentNode::write_outputs(const OutgoingSamples& samples) {
  for (const auto& kf : samples.keyframes) {
    keyframe_window_.push(kf);
    last_keyframe_seq_ = kf.seq();
  }
  write_keyframes();
  if (samples.keyframe_poses) waiting_poses_ = samples.keyframe_poses;  // a newer estimate replaces a waiting one
  for (const auto& obj : samples.objects) {
    if (objects_published_.count(obj.object_seq())) {
      waiting_objects_[obj.object_seq()] = obj;  // an update: the newest replaces one not written yet
      continue;
    }
    // A new find goes at once (ahead of everything on a budgeted link: dds::link_priority).
    if (!object_out_->write(obj)) {
      log_->error("object {} could not be queued", obj.object_seq());
      continue;
    }
    objects_published_.insert(obj.object_seq());
    log_->info("object {} ({}) confirmed after {} observations", obj.object_seq(), obj.class_name(),
               obj.observations());
  }
  send_waiting_updates();
}

void AgentNode::write_keyframes() {
  keyframe_window_.acknowledged(acked_keyframe_seq_);
  keyframe_window_.release([&](const cairn_msgs::Keyframe& kf) {
    if (!keyframe_out_->write(kf)) log_->error("keyframe {} could not be queued (history full)", kf.seq());
  });
}

bool AgentNode::send_waiting_updates() {
  // Updates of an object (a better estimate, a fuller cloud) wait until everything written before
  // has been acknowledged, and only the newest of each goes: on a 250 kbit/s radio every version
  // of every object (170 messages, 2 MB, for 27 finds on the collapsed floor) was 45 % of the
  // robots' payload. The loop-closed keyframe poses wait the same way; for them it is also what
  // keeps a keep-last sample from being replaced in flight, which Fast DDS 2.9 announces as a GAP
  // that then aborted the base's reader (DataReaderHistory::update_instance_nts; core dump).
  if (!waiting_objects_.empty() && object_out_->wait_for_acknowledgments(0.0)) {
    for (const auto& [seq, obj] : waiting_objects_) {
      if (!object_out_->write(obj)) log_->error("object {} could not be queued", seq);
    }
    waiting_objects_.clear();
  }
  if (waiting_poses_ && keyframe_poses_out_->wait_for_acknowledgments(0.0)) {
    if (!keyframe_poses_out_->write(*waiting_poses_)) {
      log_->warn("keyframe poses ({} keyframes) could not be queued", waiting_poses_->seqs().size());
    }
    waiting_poses_.reset();
  }
  return waiting_objects_.empty() && !waiting_poses_;
}

void AgentNode::publish_status(bool finished) {
  published_command_ = operator_.report();
  const AgentStats s = pipeline_.stats();
  cairn_msgs::RobotStatus st;
  st.robot_id(robot_.value);
  st.session(session_);
  const auto& traj = pipeline_.trajectory();
  st.stamp_ns(traj.empty() ? 0 : traj.back().stamp_ns);
  st.battery_pct(-1.f);  // not known: the simulator models no battery (a driver fills this in)
  st.keyframes_sent(last_keyframe_seq_ + 1);
  st.objects_sent(int32_t(objects_published_.size()));
  st.bytes_sent(int64_t(bytes_sent()));
  st.keyframe_bytes(int64_t(keyframe_out_->bytes_written()));
  st.object_bytes(int64_t(object_out_->bytes_written()));
  st.object_messages(int32_t(object_out_->samples_written()));
  st.scans_processed(s.scans_matched);
  const double now_s = std::chrono::duration<double>(Clock::now() - start_).count();
  if (now_s > last_rate_time_s_) {
    st.scan_rate_hz(float((s.scans_received - last_rate_scans_) / (now_s - last_rate_time_s_)));
  }
  last_rate_scans_ = s.scans_received;
  last_rate_time_s_ = now_s;
  if (s.scans_odometry_stalled > last_stalled_scans_) {
    log_->warn("odometry held its reading while the laser moved: {} more scans skipped ({} in all) until it resumes",
               s.scans_odometry_stalled - last_stalled_scans_, s.scans_odometry_stalled);
    last_stalled_scans_ = s.scans_odometry_stalled;
  }
  st.collision_risk(s.collision_risk >= 0.5f);  // optical-flow time-to-contact test (objects/optical_flow.h)
  st.laser_lost(pipeline_.laser_lost());
  st.finished(finished);
  dds::set_nav_status(nav_status(), &st);
  if (probe_.base_ns != 0) {
    st.probe_echo_ns(probe_.base_ns);
    st.probe_held_ns(uint64_t(std::max<int64_t>(0, dds::reception_clock_ns() - probe_.received_ns)));
  }
  status_out_->write(st);
}

uint64_t AgentNode::bytes_sent() const {
  return keyframe_out_->bytes_written() + object_out_->bytes_written() + keyframe_poses_out_->bytes_written();
}

bool AgentNode::base_has_everything() {
  return held_outputs_.empty() && earlier_.empty() && keyframe_window_.empty() &&
         acked_keyframe_seq_ >= last_keyframe_seq_ && acked_object_count_ >= int(objects_published_.size());
}

std::string AgentNode::delivery_report() const {
  return "acknowledged by the base: keyframes " + std::to_string(acked_keyframe_seq_ + 1) + " of " +
         std::to_string(last_keyframe_seq_ + 1) + ", objects " + std::to_string(acked_object_count_) + " of " +
         std::to_string(objects_published_.size()) + earlier_report();
}

int AgentNode::run(const std::atomic<bool>* stop) {
  start_ = Clock::now();
  if (log_source_)
    log_->info("replaying {} laser records from the log", log_source_->size());
  else
    log_->info("waiting for sensor data");
  log_->info("session {:08x}", session_);
  auto next_status = Clock::now();
  bool flushed = false;
  Clock::time_point flush_time;
  while (true) {
    const bool got = poll_inputs();
    if (input_finished_ && !flushed && !got) {
      // The simulator announces the end only after every reading was acknowledged, so an empty
      // poll after it means the input is complete.
      const AgentOutputs last = pipeline_.process(/*flush=*/true);
      publish(last);
      drive(last);
      flushed = true;
      flush_time = Clock::now();
      const AgentStats s = pipeline_.stats();
      size_t held = 0;  // made but not written yet: an earlier session goes first
      for (const OutgoingSamples& h : held_outputs_) held += h.keyframes.size();
      log_->info("input ended: {} scans matched, {} keyframes, {} objects; waiting for the base to store them",
                 s.scans_matched, last_keyframe_seq_ + 1 + int(held), objects_published_.size());
    } else if (!flushed) {
      const AgentOutputs outputs = pipeline_.process(false);
      publish(outputs);
      drive(outputs);
    }
    // A command's new state goes out at once: the operator waits for it (not for the next period).
    const bool command_news =
        operator_.report().seq != published_command_.seq || operator_.report().state != published_command_.state;
    resend_earlier();
    if (!held_outputs_.empty() && own_session_may_speak()) publish({});  // what was held goes now
    if ((Clock::now() >= next_status || command_news) && own_session_may_speak()) {
      publish_status(false);
      next_status = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                       std::chrono::duration<double>(options_.status_period_s));
    }
    const bool updates_written = send_waiting_updates();
    if (flushed && base_has_everything() && updates_written) break;
    if (stop && *stop) {
      if (base_has_everything()) break;
      log_->error("stopped before the base station had everything: {}", delivery_report());
      return 3;
    }
    if (flushed && options_.ack_timeout_s > 0 &&
        Clock::now() - flush_time > std::chrono::duration<double>(options_.ack_timeout_s)) {
      log_->error("the base station did not acknowledge everything within {} s: {}", options_.ack_timeout_s,
                  delivery_report());
      return 3;
    }
    if (flushed) {
      CAIRN_LOG_EVERY_N_SEC(log_, spdlog::level::info, 10.0, "waiting for the base station: {}", delivery_report());
    }
    if (!got) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  // The final loop-closed keyframe poses are not acknowledged by the base's Ack: wait for them
  // (best effort, as for a lost link the base keeps the previous estimate).
  if (!keyframe_poses_out_->wait_for_acknowledgments(2.0))
    log_->warn("final keyframe poses not acknowledged within 2 s");
  forget_own_session();
  // Status is best effort: say "finished" ten times over 2 s so the base hears it (30 % loss: all
  // ten lost one time in 170 000).
  for (int i = 0; i < 10; ++i) {
    publish_status(true);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  const AgentStats s = pipeline_.stats();
  log_->info(
      "done: {} keyframes, {} objects, {} bytes sent; {} bad samples dropped; beams: {} valid, {} NaN/inf, "
      "{} too close, {} max range",
      last_keyframe_seq_ + 1, objects_published_.size(), bytes_sent(), bad_samples_, s.beams.valid, s.beams.nan_or_inf,
      s.beams.too_close, s.beams.max_range);
  return 0;
}

}  // namespace cairn::agent
