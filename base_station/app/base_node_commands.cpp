// BaseNode's operator commands: requests the console queued (CommandInbox) are recorded
// (CommandBook), journaled and sent on cairn/operator_command in the robot's own frame; the
// robots' statuses say what became of them; a restarted base reads them back from the journal.
#include "base_station/app/base_node.h"
#include "dds/navigation_conversions.h"

#include <algorithm>

namespace cairn::base {

void BaseNode::send_operator_commands() {
  for (const VerdictRequest& v : inbox_.take_verdicts()) {
    const VerdictRecord record{v.object, v.verdict, v.note, mapper_.data().latest_stamp_ns};
    verdicts_.set(record);
    const std::string payload = verdict_record_to_json(record);
    journal(JournalKind::kVerdict, v.object.robot.value, v.object.seq,
            std::vector<uint8_t>(payload.begin(), payload.end()));
    flush_journal();
    log_->info("operator: object {} {}{}{}", object_key(v.object), to_string(v.verdict), v.note.empty() ? "" : ": ",
               v.note);
    refresh_snapshot();  // the console shows it at once
  }
  journal_alert_acks();
  take_alignments();
  apply_search_controls();  // first: a pause or resume queues its stop or resume commands
  const std::vector<CommandInbox::Entry> entries = inbox_.take_all();
  if (entries.empty()) return;
  const MergedMap merged = mapper_.merged();
  // Checked again on this thread: the robot may have been unlinked since the console's snapshot.
  const CommandCheckContext context = command_context(merged);
  for (const CommandInbox::Entry& e : entries) {
    CommandRequest one = e.request;
    one.robots = {e.robot};
    if (const auto why = check_command(one, context)) {
      log_->warn("operator command {} to {} not sent: {}", e.seq, sessions_.label(e.robot), *why);
      continue;
    }
    const OperatorCommand sent = commands_.add(e.seq, e.robot, one.kind, one.point_global_m,
                                               context.placements.at(e.robot), merged.data->latest_stamp_ns);
    const CommandRecord& record = commands_.records().back();
    const std::string payload = command_record_to_json(record);
    journal(JournalKind::kCommand, e.robot.value, e.seq, std::vector<uint8_t>(payload.begin(), payload.end()));
    cairn_msgs::OperatorCommand out = dds::to_msg(sent);
    address(e.robot, &out);  // check_command refused a session that ended
    if (!command_out_->write(out)) {
      log_->warn(
          "operator command {} to {}: the write timed out (the newest command is sent again when the link is "
          "back)",
          e.seq, sessions_.label(e.robot));
    }
    if (one.kind == CommandKind::kGoTo) {
      log_->info("operator: {} {} to ({:.1f}, {:.1f}) m (command {})", sessions_.label(e.robot), to_string(one.kind),
                 one.point_global_m.x(), one.point_global_m.y(), e.seq);
    } else {
      log_->info("operator: {} {} (command {})", sessions_.label(e.robot), to_string(one.kind), e.seq);
    }
  }
  flush_journal();
  inbox_.post_states(commands_json(commands_.records()));
  replan_now_ = true;  // a robot left to, or taken back from, the operator
}

bool BaseNode::restore_command(const JournalRecord& r, std::string* error) {
  const auto record = command_record_from_json(std::string(r.payload.begin(), r.payload.end()), error);
  if (!record) return false;
  if (record->robot != r.robot || int64_t(record->seq) != r.key) {
    *error = "operator command record: its robot and seq differ from the journal's key";
    return false;
  }
  commands_.restore({record->robot, record->seq, record->kind, record->point_local_m}, record->point_global_m,
                    record->sent_ns);
  return true;
}

void BaseNode::apply_search_controls() {
  for (const SearchControlRequest& request : inbox_.take_search()) {
    if (const auto why = search_.check(request)) {
      log_->warn("operator: {} not applied: {}", to_string(request.action), *why);
      continue;
    }
    // A pause stops every robot exploring on its own (not the ones the operator drives); resuming
    // hands back those still stopped by it.
    std::vector<RobotId> robots;
    for (const RobotSummary& r : mapper_.robots()) {
      const bool exploring = !commands_.under_operator(r.id);
      const bool held_by_pause = std::find(search_.stopped_by_pause().begin(), search_.stopped_by_pause().end(),
                                           r.id) != search_.stopped_by_pause().end() &&
                                 commands_.newest_kind(r.id) == CommandKind::kStop;
      if (request.action == SearchAction::kPause ? exploring : held_by_pause) robots.push_back(r.id);
    }
    const SearchControlRecord record = search_.apply(request, robots, mapper_.data().latest_stamp_ns);
    const std::string payload = search_record_to_json(record);
    journal(JournalKind::kSearch, 0, record.seq, std::vector<uint8_t>(payload.begin(), payload.end()));
    flush_journal();
    if (request.action == SearchAction::kPause && !robots.empty()) inbox_.push({robots, CommandKind::kStop, {0, 0}});
    if (request.action == SearchAction::kResume && !robots.empty()) inbox_.push({robots, CommandKind::kResume, {0, 0}});
    if (request.action == SearchAction::kKeepOut) {
      log_->info("operator: keep-out area {} [{:.1f}, {:.1f}] x [{:.1f}, {:.1f}] m", record.area.id,
                 record.area.min_m.x(), record.area.max_m.x(), record.area.min_m.y(), record.area.max_m.y());
    } else {
      log_->info("operator: {}{}", to_string(request.action),
                 record.area.id ? " " + std::to_string(record.area.id) : std::string());
    }
    inbox_.post_search(search_);
    replan_now_ = true;
  }
}

bool BaseNode::restore_search(const JournalRecord& r, std::string* error) {
  const auto record = search_record_from_json(std::string(r.payload.begin(), r.payload.end()), error);
  if (!record) return false;
  if (int64_t(record->seq) != r.key) {
    *error = "search control record: its seq differs from the journal's key";
    return false;
  }
  return search_.restore(*record, error);
}

bool BaseNode::restore_verdict(const JournalRecord& r, std::string* error) {
  const auto record = verdict_record_from_json(std::string(r.payload.begin(), r.payload.end()), error);
  if (!record) return false;
  if (record->object.robot != r.robot || record->object.seq != r.key) {
    *error = "verdict record: its object differs from the journal's key";
    return false;
  }
  verdicts_.set(*record);
  return true;
}

void BaseNode::journal_alert_acks() {
  bool any = false;
  for (const std::string& key : inbox_.acked_alerts()) {
    if (!journaled_alert_acks_.insert(key).second) continue;
    const std::string payload = alert_ack_to_json(key);
    journal(JournalKind::kAlertAck, 0, ++last_alert_ack_key_, std::vector<uint8_t>(payload.begin(), payload.end()));
    log_->info("operator: alert {} acknowledged", key);
    any = true;
  }
  if (!any) return;
  flush_journal();
  refresh_snapshot(/*full=*/false);  // the console's alert log shows it at once, not at the next map change
}

bool BaseNode::restore_alert_ack(const JournalRecord& r, std::string* error) {
  last_alert_ack_key_ = std::max(last_alert_ack_key_, r.key);  // a damaged record's key is not reused either
  const auto key = alert_ack_from_json(std::string(r.payload.begin(), r.payload.end()), error);
  if (!key) return false;
  journaled_alert_acks_.insert(*key);
  inbox_.ack_alert(*key);  // shown acknowledged as soon as it is raised again
  return true;
}

bool BaseNode::take_alignments() {
  const std::vector<AlignmentRequest> requests = inbox_.take_alignments();
  for (const AlignmentRequest& a : requests) {
    if (!mapper_.request_alignment(a.robot, a.T_global_local)) continue;  // parse_alignment_request checked it
    const std::string payload = alignment_request_to_json(a);
    journal(JournalKind::kAlignment, a.robot.value, 0, std::vector<uint8_t>(payload.begin(), payload.end()));
    log_->info("operator: {} aligned at ({:.2f}, {:.2f}) m, {:.1f} deg: verifying", sessions_.label(a.robot),
               a.T_global_local.x(), a.T_global_local.y(), a.T_global_local.yaw() * 180.0 / M_PI);
  }
  if (requests.empty()) return false;
  flush_journal();
  refresh_snapshot(/*full=*/false);  // the console shows "verifying" at once
  return true;
}

bool BaseNode::restore_alignment(const JournalRecord& r, std::string* error) {
  const auto a = alignment_request_from_json(std::string(r.payload.begin(), r.payload.end()), error);
  if (!a) return false;
  if (a->robot != r.robot) return *error = "alignment record: its robot differs from the journal's", false;
  return mapper_.request_alignment(a->robot, a->T_global_local);  // judged again once the keyframes are back
}

MergedMap BaseNode::judged_map() const {
  MergedMap merged = mapper_.merged();
  verdicts_.apply(&merged.objects);
  verdicts_.apply(&merged.unplaced_objects);
  return merged;
}

void BaseNode::after_restore_commands() {
  // Statuses are replayed before commands: apply each robot's newest report to its commands now.
  for (const auto& [robot, nav] : navigation_) commands_.on_report(robot, nav.command);
  inbox_.start_after(commands_.last_seq());
  inbox_.post_search(search_);
  inbox_.post_states(commands_json(commands_.records()));
  if (!commands_.records().empty()) log_->info("journal: {} operator commands", commands_.records().size());
}

void BaseNode::note_command_report(RobotId robot, const CommandReport& report, bool live) {
  if (!commands_.on_report(robot, report)) return;
  inbox_.post_states(commands_json(commands_.records()));
  if (!live) return;
  for (const CommandRecord& r : commands_.records()) {
    if (r.robot == robot && r.seq == report.seq) {
      log_->info("operator command {} to {}: {}{}{}", r.seq, sessions_.label(robot), to_string(r.state),
                 r.note.empty() ? "" : ", ", r.note);
    }
  }
}

CommandCheckContext BaseNode::command_context(const MergedMap& merged) const {
  CommandCheckContext c;
  c.placements = merged.placements();
  for (const auto& [robot, link] : links_) c.placements.emplace(robot, std::nullopt);  // heard of, no data yet
  const OccupancyGrid& grid = *merged.grid;
  c.has_map = grid.known_area_m2() > 0;
  c.map_min_m = grid.origin_m();
  c.map_max_m = grid.origin_m() + Eigen::Vector2d(grid.width(), grid.height()) * grid.resolution_m();
  c.keep_out = search_.keep_out();
  c.exploration_paused = search_.paused();
  for (const auto& [robot, placement] : c.placements) {
    const auto s = sessions_.find(robot);
    if (s && !sessions_.is_current(robot)) c.ended_sessions[robot] = sessions_.current(s->robot);
  }
  return c;
}

}  // namespace cairn::base
