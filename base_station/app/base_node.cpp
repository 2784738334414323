#include "base_station/app/base_node.h"

#include <algorithm>
#include <fstream>
#include <thread>

#include "base_station/console/search_api.h"
#include "base_station/export/exporter.h"
#include "dds/cdr.h"
#include "dds/conversions.h"
#include "dds/navigation_conversions.h"

namespace cairn::base {

using Clock = std::chrono::steady_clock;

namespace {

/// Highest seq such that every keyframe 0..seq of `robot` is stored (-1 = none).
int32_t contiguous_seq(const MultiRobotMapper& mapper, RobotId robot) {
  const auto& kfs = mapper.keyframes();
  int32_t expected = 0;
  for (auto it = kfs.lower_bound(KeyframeId{robot, 0}); it != kfs.end() && it->first.robot == robot; ++it) {
    if (it->first.seq != expected) break;
    ++expected;
  }
  return expected - 1;
}

}  // namespace

BaseNode::BaseNode(const BaseNodeOptions& options, const MapperOptions& mapper_options)
    : options_(options), mapper_options_(mapper_options), mapper_(mapper_options), log_(make_logger("base")) {
  meetings_ = ActiveLinker(options.active_linking);
  for (const auto& [robot, start] : options_.robot_starts) mapper_.set_robot_start(robot, start);
  for (const auto& [robot, hint] : options_.entry_hints) mapper_.set_entry_hint(robot, hint);
}

std::unique_ptr<BaseNode> BaseNode::create(const BaseNodeOptions& options, const MapperOptions& mapper_options,
                                           std::string* error) {
  std::unique_ptr<BaseNode> n(new BaseNode(options, mapper_options));
  dds::ParticipantOptions po;
  po.domain_id = options.domain_id;
  po.name = "cairn_base";
  po.initial_peers = options.peers;
  po.use_shared_memory = options.use_shared_memory;
  if (options.slow_link) {
    po.announcement_period_s = dds::kSlowLinkAnnouncementPeriod_s;
    po.lease_duration_s = dds::kSlowLinkLeaseDuration_s;
  }
  po.security_dir = options.security_dir;
  n->participant_ = dds::Participant::create(po, error);
  if (!n->participant_) return nullptr;
  auto& p = *n->participant_;
  n->keyframe_in_ = std::make_unique<dds::Reader<dds::KeyframeTopic>>(p);
  n->object_in_ = std::make_unique<dds::Reader<dds::ObjectTopic>>(p);
  n->status_in_ = std::make_unique<dds::Reader<dds::StatusTopic>>(p);
  n->keyframe_poses_in_ = std::make_unique<dds::Reader<dds::KeyframePosesTopic>>(p);
  dds::QosOptions to_robots;  // on a slow radio, fewer heartbeats (dds/qos.h)
  if (options.slow_link) to_robots.heartbeat_period_s = dds::kSlowLinkHeartbeat_s;
  n->ack_out_ = std::make_unique<dds::Writer<dds::AckTopic>>(p, to_robots);
  if (options.ros2) {
    n->ros2_out_ = std::make_unique<Ros2Output>(p);
    if (!n->ros2_out_->ok()) {
      *error = "cannot create the ROS 2 output writers";
      return nullptr;
    }
  }
  n->correction_out_ = std::make_unique<dds::Writer<dds::CorrectionTopic>>(p, to_robots);
  n->goal_out_ = std::make_unique<dds::Writer<dds::GoalTopic>>(p, to_robots);
  n->command_out_ = std::make_unique<dds::Writer<dds::OperatorCommandTopic>>(p, to_robots);
  n->keep_out_out_ = std::make_unique<dds::Writer<dds::KeepOutTopic>>(p, to_robots);
  if (!n->keyframe_in_->ok() || !n->object_in_->ok() || !n->status_in_->ok() || !n->keyframe_poses_in_->ok() ||
      !n->ack_out_->ok() || !n->correction_out_->ok() || !n->goal_out_->ok() || !n->command_out_->ok() ||
      !n->keep_out_out_->ok()) {
    *error = "cannot create the base station's DDS readers/writers";
    return nullptr;
  }
  if (!n->open_journal(error)) return nullptr;
  BaseNode* self = n.get();
  n->console_ = std::make_unique<ConsoleServer>(
      options.console, ConsoleServer::SharedProvider([self] { return self->latest_snapshot_.get(); }));
  n->refresh_snapshot();  // the console's first answers (and command checks) see the restored mission
  n->console_->accept_commands(options.operator_token, &n->inbox_);  // an empty token: the list only
  if (!n->console_->start(error)) return nullptr;
  return n;
}

double BaseNode::now_s() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

void BaseNode::publish_acks_and_corrections() {
  const bool all_journaled = unjournaled_.empty();  // an ack promises the sample survives a restart
  for (const RobotSummary& r : mapper_.robots()) {
    cairn_msgs::Ack ack;
    const bool current = address(r.id, &ack);
    if (all_journaled) {
      ack.keyframe_seq(contiguous_seq(mapper_, r.id));
      ack.object_count(r.objects);
      // A session that ended (the robot runs a newer one) is acked when what it holds grew and
      // every 5 s (acks are volatile: one written before the restarted agent's reader matched is
      // never delivered): the restarted agent resends that session's outbox
      // (robot_agent/app/outbox.h) and deletes what the base has. Acks are keyed by session.
      const EndedSessionAck held{ack.keyframe_seq(), ack.object_count(), now_s()};
      const auto last = ended_session_acks_.find(r.id);
      if (current || last == ended_session_acks_.end() || last->second.keyframe_seq != held.keyframe_seq ||
          last->second.objects != held.objects || held.written_s - last->second.written_s >= 5.0) {
        if (current) ack.probe_ns(uint64_t(dds::reception_clock_ns()));  // echoed: the link's round trip
        if (ack_out_->write(ack) && !current) ended_session_acks_[r.id] = held;
      }
    }
    if (!current) continue;  // corrections, goals and keep-out areas only for the session running
    cairn_msgs::Correction c;
    address(r.id, &c);
    c.linked(r.linked);
    c.T_global_local(dds::to_msg(r.T_global_local));
    correction_out_->write(c);
    send_keep_out(r);
  }
}

void BaseNode::send_keep_out(const RobotSummary& r) {
  KeepOutRobotState state;
  state.robot = r.id;
  state.linked = r.linked;
  state.T_global_local = r.T_global_local;
  if (const auto nav = navigation_.find(r.id); nav != navigation_.end())
    state.held_version = nav->second.keep_out_version;
  const auto message = keep_out_relay_.due(state, search_.keep_out(), now_s());
  if (!message) return;
  cairn_msgs::KeepOutAreas m = dds::to_msg(*message);
  address(r.id, &m);
  if (!keep_out_out_->write(m)) return;  // not sent: due() offers it again next tick
  keep_out_relay_.mark_sent(state, search_.keep_out(), *message, now_s());
  log_->info("keep-out areas sent to {}: {} (version {})", sessions_.label(r.id), message->areas.size(),
             message->version);
}

bool BaseNode::all_finished() const {
  if (options_.expected_robots <= 0) return false;
  int finished = 0;
  for (const auto& [robot, link] : links_) {  // a robot counts once: the session it runs now
    finished += sessions_.is_current(robot) && link.has_status && link.last_status.finished();
  }
  return finished >= options_.expected_robots;
}

void BaseNode::report_linking(const OptimizeResult& r) {
  for (const LinkEvent& e : r.link_events) {
    if (e.accepted) {  // reported below, once per robot; here only how, when that was not scan closures
      if (e.reason != "linked")
        log_->info("link {} <-> {}: {}", sessions_.label(e.robot), sessions_.label(e.other), e.reason);
      continue;
    }
    log_->info("link {} <-> {} via {} closures {}: {} (map contradiction {:.1f} %)", sessions_.label(e.robot),
               sessions_.label(e.other), e.closures, e.inconclusive ? "deferred" : "rejected", e.reason,
               100.0 * e.contradiction_ratio);
  }
  for (RobotId robot : r.newly_linked) {
    int closures = 0;
    for (const RobotSummary& s : mapper_.robots()) {
      if (s.id == robot) closures = s.inter_robot_closures;
    }
    log_->info("{} linked into the global map through {} verified cross-robot closures", sessions_.label(robot),
               closures);
  }
  const auto& marker_events = mapper_.landmark_link_events();
  for (; landmark_events_reported_ < marker_events.size(); ++landmark_events_reported_) {
    const LinkEvent& e = marker_events[landmark_events_reported_];
    log_->info("marker or sighting link {} <-> {}: {}", sessions_.label(e.robot), sessions_.label(e.other), e.reason);
  }
  for (const auto& [robot, v] : mapper_.alignments()) {  // each verdict once (pending ones are logged on request)
    const std::string said = std::string(to_string(v.state)) + v.reason;
    if (v.state == AlignmentState::kPending || alignments_reported_[robot] == said) continue;
    alignments_reported_[robot] = said;
    log_->info("operator alignment of {} {}: {}", sessions_.label(robot), to_string(v.state), v.reason);
  }
  CAIRN_LOG_EVERY_N_SEC(log_, spdlog::level::info, 10.0,
                        "graph: {} nodes, {} loop closures ({} between robots), {} candidates pending, "
                        "{} robots not linked yet",
                        r.nodes, r.loop_closures, r.inter_robot_closures, r.pending_candidates, r.unlinked_robots);
}

int BaseNode::run() {
  log_->info("console at http://{}:{}/  (domain {}, expecting {} robots)", options_.console.bind_address,
             console_->port(), options_.domain_id, options_.expected_robots);
  if (!options_.operator_token.empty()) {
    log_->info("operator console (commands the robots): http://{}:{}/#token={}", options_.console.bind_address,
               console_->port(), options_.operator_token);
  }
  auto next_optimize = Clock::now();
  const auto period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options_.optimize_period_s));
  auto next_plan = Clock::now();
  const auto plan_period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options_.exploration_period_s));
  while (!stop_) {
    const bool got = poll_inputs();
    send_operator_commands();
    // A new keyframe shows in an open console soon, not only at the next optimise tick.
    if (unshown_keyframe_wall_s_ > 0 && console_->open_streams() > 0 &&
        Clock::now() - last_snapshot_ >= std::chrono::duration<double>(options_.console_update_s))
      refresh_snapshot(/*full=*/false);
    if (Clock::now() >= next_optimize) {
      if (mapper_.version() != optimized_version_) {
        const OptimizeResult r = mapper_.optimize();
        optimized_version_ = mapper_.version();
        if (!r.solve.converged) log_->warn("pose graph did not converge: {}", r.solve.reason);
        report_linking(r);
      }
      publish_acks_and_corrections();
      if ((Clock::now() >= next_plan && mapper_.version() != planned_version_) || replan_now_) {
        plan_and_publish_goals();
        next_plan = Clock::now() + plan_period;
      }
      refresh_snapshot();
      record_coverage(mapper_.merged());
      publish_ros2();
      next_optimize = Clock::now() + period;
    }
    if (all_finished()) break;
    if (!got) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return finish();
}

int BaseNode::finish() {
  int code = write_results();
  if (options_.serve_after_finish) {
    log_->info("serving the console at http://{}:{}/ until stopped (Ctrl-C)", options_.console.bind_address,
               console_->port());
    while (!stop_) {
      // The operator may still align a robot the base could not place: judged, results written again.
      if (take_alignments()) code = write_results();
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  }
  console_->stop();
  return code;
}

int BaseNode::write_results() {
  OptimizeResult r = mapper_.optimize();
  report_linking(r);  // an operator's alignment is judged here too
  // The final map: solve the last loop closures to convergence (bounded, each call iterates a few).
  for (int i = 0; i < 50 && mapper_.refinement_pending(); ++i) r = mapper_.optimize();
  plan_and_publish_goals(/*send=*/false);  // where to search next, on the final map (the robots are done)
  refresh_snapshot();
  publish_ros2();
  const MergedMap merged = judged_map();
  const ExportSummary exported = export_all(merged, options_.out_dir, {}, &plan_);
  for (const auto& f : exported.files) {
    if (!f.ok) log_->error("export of {} failed: {}", f.path, f.error);
  }
  console_->offer_exports(options_.out_dir);  // downloadable from the console from now on
  nlohmann::json summary;
  summary["robots"] = nlohmann::json::array();
  const nlohmann::json links = link_stats();
  // Every robot the base heard of: from its data, or only from its statuses (none of its data arrived).
  std::vector<RobotSummary> robots = mapper_.robots();
  for (const auto& entry : links_) {
    const RobotId id = entry.first;
    if (std::none_of(robots.begin(), robots.end(), [&](const RobotSummary& r) { return r.id == id; })) {
      RobotSummary r;
      r.id = id;
      robots.push_back(r);
    }
  }
  std::sort(robots.begin(), robots.end(), [](const RobotSummary& a, const RobotSummary& b) { return a.id < b.id; });
  for (const RobotSummary& rs : robots) {
    nlohmann::json j;
    j["id"] = rs.id.value;
    j["label"] = sessions_.label(rs.id);
    if (const auto session = sessions_.find(rs.id)) {
      j["robot"] = session->robot.value;  // the robot id on the wire; differs from "id" after a restart
      j["session"] = session->ordinal;
    }
    j["linked"] = rs.linked;
    j["anchor"] = rs.anchor;
    if (const auto start = options_.robot_starts.find(rs.id); start != options_.robot_starts.end())
      j["given_start"] = {{"x_m", start->second.x()}, {"y_m", start->second.y()}, {"yaw_rad", start->second.yaw()}};
    j["inter_robot_closures"] = rs.inter_robot_closures;
    j["keyframes"] = rs.keyframes;
    j["missing_keyframes"] = rs.missing_keyframes;
    j["object_reports"] = rs.objects;
    j["first_stamp_s"] = ns_to_sec(rs.first_stamp_ns);
    j["time_to_link_s"] = rs.time_to_link_s >= 0 ? nlohmann::json(rs.time_to_link_s) : nlohmann::json();
    const std::string key = std::to_string(rs.id.value);
    j["link"] = links.contains(key) ? links[key] : nlohmann::json::object();
    summary["robots"].push_back(j);
  }
  summary["objects"] = merged.objects.size();
  // Never quiet about what is not on the map: the robots not placed and their finds, in their own frame.
  summary["unlinked_robots"] = nlohmann::json::array();
  for (const RobotSummary& rs : robots) {
    if (!rs.linked) summary["unlinked_robots"].push_back(rs.id.value);
  }
  summary["unplaced_objects"] = nlohmann::json::array();
  for (const GlobalObject& o : merged.unplaced_objects) summary["unplaced_objects"].push_back(object_json(o, merged));
  summary["mapped_area_m2"] = mapper_.mapped_area_m2();
  summary["graph"] = {{"nodes", r.nodes},
                      {"edges", r.edges},
                      {"loop_closures", r.loop_closures},
                      {"inter_robot_closures", r.inter_robot_closures},
                      {"unlinked_robots", r.unlinked_robots},
                      {"converged", r.solve.converged},
                      {"final_cost", r.solve.final_cost}};
  summary["exploration"] = exploration_json(plan_);
  summary["search"] = search_json(search_);  // the operator's pause and keep-out areas
  summary["exploration"]["goals_blacklisted"] = goals_.goals_blacklisted();
  size_t salient_spots = 0;  // what the cameras sent for the saliency layer
  for (const auto& [id, kf] : mapper_.data().keyframes) salient_spots += kf.salient.size();
  summary["exploration"]["salient_spots_received"] = salient_spots;
  summary["exploration"]["sent_home"] = goals_.sent_home();
  const ActiveLinkingStats& meetings = meetings_.stats();  // active linking: robots sent to meet a teammate
  summary["exploration"]["meetings"] = {
      {"started", meetings.started}, {"linked", meetings.linked}, {"failed", meetings.failed}};
  if (const auto home_ns = goals_.sent_home_at_ns()) summary["exploration"]["sent_home_at_s"] = ns_to_sec(*home_ns);
  summary["coverage_series"] = coverage_series_;
  summary["commands"] = commands_json(commands_.records(), commands_.records().size());
  summary["alerts_acknowledged"] = journaled_alert_acks_;  // the operator's, across restarts
  summary["verdicts"] = nlohmann::json::array();           // the operator's, as given (objects.csv: as applied)
  for (const auto& [id, v] : verdicts_.records())
    summary["verdicts"].push_back({{"object", object_key(id)}, {"verdict", to_string(v.verdict)}, {"note", v.note}});
  summary["alignments"] = nlohmann::json::array();  // the operator's latest per robot, and the verdict
  for (const auto& [robot, a] : mapper_.alignments())
    summary["alignments"].push_back({{"robot", robot.value},
                                     {"x_m", a.requested.x()},
                                     {"y_m", a.requested.y()},
                                     {"yaw_deg", a.requested.yaw() * 180.0 / M_PI},
                                     {"state", to_string(a.state)},
                                     {"reason", a.reason}});
  summary["rejected_samples"] = rejected_samples_;
  summary["refused_overwrites"] = refused_overwrites_;
  summary["spoofed_samples"] = spoofed_samples_;  // with DDS Security: a robot id its writer's certificate is not
  summary["restarts"] = nlohmann::json::array();  // robots that restarted without their state
  for (const RobotSession& s : sessions_.restarts()) {
    summary["restarts"].push_back({{"robot", s.robot.value},
                                   {"session", s.ordinal},
                                   {"base_id", s.base_id.value},
                                   {"label", sessions_.label(s.base_id)}});
  }
  summary["journal"] = {{"path", journal_->path()},
                        {"records", journal_->size()},
                        {"restored_records", restored_records_},
                        {"skipped_records", restore_skipped_.size()},
                        {"unjournaled", unjournaled_.size()},
                        {"commits", journal_commits_},
                        {"commit_s", journal_commit_s_}};
  summary["landmarks"] = nlohmann::json::array();  // identified markers, global frame
  for (const auto& [id, p] : mapper_.landmarks())
    summary["landmarks"].push_back({{"id", id.value}, {"x_m", p.x()}, {"y_m", p.y()}});
  summary["export_ok"] = exported.ok();
  std::ofstream out(options_.out_dir + "/summary.json");
  out << summary.dump(2) << "\n";
  if (!out) {
    log_->error("cannot write {}/summary.json", options_.out_dir);
    return 4;
  }
  log_->info("mission merged: {} robots, {} objects, {:.1f} m2 mapped; results in {}", mapper_.robots().size(),
             mapper_.objects().size(), mapper_.mapped_area_m2(), options_.out_dir);
  return exported.ok() ? 0 : 5;
}

}  // namespace cairn::base
