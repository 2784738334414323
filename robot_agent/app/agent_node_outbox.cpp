// The agent's outbox on disk (robot_agent/app/outbox.h) around AgentNode: what this run produces is
// stored before it is written to DDS and deleted once the base acknowledges it; what earlier runs
// of this robot left unacknowledged (the process was killed, the robot lost power) is resent first,
// each under its own session id, and this run stays silent until the base has heard every earlier
// session: the base takes the session it hears of last as the one the robot runs now
// (base_station/core/robot_sessions.h), so the order it hears them in must be the order they ran.
#include "dds/cdr.h"
#include "dds/conversions.h"
#include "robot_agent/app/agent_node.h"

namespace cairn::agent {

namespace {

/// Earlier records written per poll: the loop stays responsive while a long backlog goes out.
constexpr size_t kResendPerPoll = 100;
/// With the base heard from (acks for other robots) but an earlier session never acknowledged
/// (its records refused), this run speaks after this long rather than stay silent for ever.
constexpr double kEarlierSessionSilence_s = 60.0;

}  // namespace

bool AgentNode::open_outbox(std::string* error) {
  outbox_ = Outbox::open(options_.outbox_path, robot_, error);
  if (!outbox_) return false;
  std::vector<OutboxSession> earlier = outbox_->earlier_sessions(session_, error);
  if (!error->empty()) return false;
  for (OutboxSession& s : earlier) {
    log_->warn(
        "outbox {}: an earlier run (session {:08x}) left undelivered {} records (up to keyframe {}, {} objects): "
        "resending them first, under that session",
        outbox_->path(), s.session, s.items.size(), s.last_keyframe_seq, s.objects);
    earlier_.push_back(EarlierSession{std::move(s)});
  }
  return true;
}

void AgentNode::keep(const OutgoingSamples& samples) {
  if (!outbox_) return;
  std::vector<OutboxItem> items;
  for (const auto& kf : samples.keyframes)
    items.push_back({OutboxKind::kKeyframe, kf.seq(), dds::to_cdr<dds::KeyframeTopic::PubSub>(kf)});
  for (const auto& obj : samples.objects)
    items.push_back({OutboxKind::kObject, obj.object_seq(), dds::to_cdr<dds::ObjectTopic::PubSub>(obj)});
  if (samples.keyframe_poses)
    items.push_back(
        {OutboxKind::kKeyframePoses, 0, dds::to_cdr<dds::KeyframePosesTopic::PubSub>(*samples.keyframe_poses)});
  std::string error;
  if (!outbox_->put(session_, items, &error))
    CAIRN_LOG_EVERY_N_SEC(log_, spdlog::level::err, 5.0, "not kept on disk (a reboot would lose it): {}", error);
}

bool AgentNode::own_session_may_speak() {
  if (earlier_.empty()) return true;
  bool all_heard = true;
  for (const EarlierSession& e : earlier_) all_heard = all_heard && e.heard;
  if (all_heard) return true;
  const double now_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const EarlierSession& front = earlier_.front();
  if (heard_any_ack_ && front.written == front.held.items.size() && front.written_at_s >= 0 &&
      now_s - front.written_at_s > kEarlierSessionSilence_s) {
    CAIRN_LOG_EVERY_N_SEC(log_, spdlog::level::warn, 60.0,
                          "the base has not acknowledged earlier session {:08x} in {} s although it answers: this run "
                          "speaks now",
                          front.held.session, kEarlierSessionSilence_s);
    return true;
  }
  return false;
}

void AgentNode::resend_earlier() {
  // Sessions go in the order they ran: the next one only once the base has heard the one before.
  size_t budget = kResendPerPoll;
  for (EarlierSession& e : earlier_) {
    while (budget > 0 && e.written < e.held.items.size()) {
      const OutboxItem& item = e.held.items[e.written];
      bool written = true, decoded = true;
      if (item.kind == OutboxKind::kKeyframe) {
        cairn_msgs::Keyframe m;
        decoded = dds::from_cdr<dds::KeyframeTopic::PubSub>(item.payload, &m);
        written = !decoded || keyframe_out_->write(m);
      } else if (item.kind == OutboxKind::kObject) {
        cairn_msgs::ObjectReport m;
        decoded = dds::from_cdr<dds::ObjectTopic::PubSub>(item.payload, &m);
        written = !decoded || object_out_->write(m);
      } else {
        // Keep last, one per robot: written only once what went before is acknowledged (why: the
        // comment in send_waiting_updates).
        if (!keyframe_poses_out_->wait_for_acknowledgments(0.0)) return;
        cairn_msgs::KeyframePoses m;
        decoded = dds::from_cdr<dds::KeyframePosesTopic::PubSub>(item.payload, &m);
        written = !decoded || keyframe_poses_out_->write(m);
      }
      if (!decoded) log_->error("outbox: session {:08x}'s record {} cannot be read: skipped", e.held.session, item.seq);
      if (!written) return;  // the writer's queue is full: the rest next poll
      ++e.written;
      --budget;
    }
    if (e.written == e.held.items.size() && e.written_at_s < 0)
      e.written_at_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (!e.heard || budget == 0) return;
  }
}

void AgentNode::take_earlier_ack(const cairn_msgs::Ack& a) {
  if (a.robot_id() != robot_.value) return;
  for (auto it = earlier_.begin(); it != earlier_.end(); ++it) {
    if (it->held.session != a.session()) continue;
    it->heard = true;
    std::string error;
    if (a.keyframe_seq() > it->acked_keyframe_seq) {
      it->acked_keyframe_seq = a.keyframe_seq();
      if (!outbox_->acknowledged(it->held.session, it->acked_keyframe_seq, &error)) log_->error("{}", error);
    }
    it->acked_objects = std::max(it->acked_objects, int32_t(a.object_count()));
    const bool delivered = it->written == it->held.items.size() &&
                           it->acked_keyframe_seq >= it->held.last_keyframe_seq &&
                           it->acked_objects >= it->held.objects;
    if (!delivered) return;
    log_->info("earlier session {:08x}: the base has all it left (up to keyframe {}, {} objects)", it->held.session,
               it->held.last_keyframe_seq, it->held.objects);
    if (!outbox_->forget(it->held.session, &error)) log_->error("{}", error);
    earlier_.erase(it);
    return;
  }
}

void AgentNode::note_own_ack() {
  if (!outbox_ || acked_keyframe_seq_ <= outbox_acked_seq_) return;
  std::string error;
  if (outbox_->acknowledged(session_, acked_keyframe_seq_, &error))
    outbox_acked_seq_ = acked_keyframe_seq_;
  else
    CAIRN_LOG_EVERY_N_SEC(log_, spdlog::level::err, 5.0, "{}", error);
}

void AgentNode::forget_own_session() {
  std::string error;
  if (outbox_ && !outbox_->forget(session_, &error)) log_->error("{}", error);
}

std::string AgentNode::earlier_report() const {
  if (earlier_.empty()) return "";
  size_t records = 0;
  for (const EarlierSession& e : earlier_) records += e.held.items.size();
  return "; earlier sessions not delivered: " + std::to_string(earlier_.size()) + " (" + std::to_string(records) +
         " records kept in " + outbox_->path() + ")";
}

}  // namespace cairn::agent
