// BaseNode's samples in: each robot's keyframes, keyframe poses, objects and statuses from DDS,
// resolved to the robot's session (RobotSessions: a robot that restarted is kept apart), validated
// (dds::from_msg), handed to the mapper, and journaled before any ack covers them.
#include "base_station/app/base_node.h"
#include "dds/cdr.h"
#include "dds/conversions.h"
#include "dds/navigation_conversions.h"

namespace cairn::base {

namespace {

void set_robot(Keyframe* kf, RobotId robot) { kf->id.robot = robot; }
void set_robot(KeyframePoses* poses, RobotId robot) { poses->robot = robot; }
void set_robot(ObjectReport* report, RobotId robot) { report->id.robot = robot; }

}  // namespace

template <typename Msg, typename Add>
AddResult BaseNode::convert_and_add(const Msg& m, std::optional<RobotId>* robot, Add&& add) {
  std::string error;
  auto parsed = dds::from_msg(m, &error);
  if (!parsed) return AddResult{AddStatus::kRejected, error};
  *robot = base_id(m.robot_id(), m.session());  // only for a valid sample: a bad one starts no session
  set_robot(&*parsed, **robot);
  return add(*parsed);
}

void BaseNode::count_rejected(int32_t robot_id) {
  ++rejected_samples_;
  ++links_[RobotId(robot_id)].bad_samples;
}

std::optional<RobotId> BaseNode::base_id(int32_t robot_id, uint32_t session) {
  if (robot_id < 0 || robot_id >= RobotSessions::kFirstRestartId) return std::nullopt;  // from_msg says why
  bool is_new = false;
  const RobotId id = sessions_.resolve(RobotId(robot_id), session, &is_new);
  if (!is_new) return id;
  const RobotSession s = *sessions_.find(id);
  const std::string record = session_record_to_json(s);
  journal(JournalKind::kSession, id.value, s.session, std::vector<uint8_t>(record.begin(), record.end()));
  if (s.ordinal > 1) {
    log_->warn(
        "{} started session {:08x} ({} of this robot): it restarted without its state, so its data from now on is "
        "'{}' (base id {}), kept apart from what it sent before and placed by closures like any robot",
        to_string(s.robot), s.session, s.ordinal, sessions_.label(id), id.value);
    replan_now_ = true;  // the old session gets no more goals
  }
  return id;
}

void BaseNode::count_refused(const AddResult& r, RobotId robot, const char* what) {
  if (r.status == AddStatus::kConflict) {
    ++refused_overwrites_;
    log_->warn("refused {} of {}: {}", what, sessions_.label(robot), r.reason);
  }
}

AddResult BaseNode::ingest(const cairn_msgs::Keyframe& m) {
  std::optional<RobotId> robot;
  const AddResult r = convert_and_add(m, &robot, [&](const Keyframe& kf) { return mapper_.add_keyframe(kf); });
  if (r.status != AddStatus::kRejected) note_keyframe_arrival();
  if (r.status == AddStatus::kRejected) {
    count_rejected(m.robot_id());
    CAIRN_LOG_EVERY_N_SEC(log_, spdlog::level::warn, 2.0, "rejected keyframe robot{}/{}: {}", m.robot_id(), m.seq(),
                          r.reason);
  }
  if (robot) count_refused(r, *robot, "a keyframe");
  return r;
}

AddResult BaseNode::ingest(const cairn_msgs::KeyframePoses& m) {
  std::optional<RobotId> robot;
  const AddResult r = convert_and_add(m, &robot, [&](const KeyframePoses& p) { return mapper_.add_keyframe_poses(p); });
  if (r.status == AddStatus::kRejected) {
    count_rejected(m.robot_id());
    CAIRN_LOG_EVERY_N_SEC(log_, spdlog::level::warn, 2.0, "rejected keyframe poses of robot{}: {}", m.robot_id(),
                          r.reason);
  } else if (r.stored()) {
    ++links_[*robot].keyframe_pose_updates;
  }
  return r;
}

AddResult BaseNode::ingest(const cairn_msgs::ObjectReport& m) {
  std::optional<RobotId> robot;
  const AddResult r = convert_and_add(m, &robot, [&](const ObjectReport& o) { return mapper_.add_object(o); });
  if (r.status == AddStatus::kRejected) {
    count_rejected(m.robot_id());
    CAIRN_LOG_EVERY_N_SEC(log_, spdlog::level::warn, 2.0, "rejected object robot{}/{}: {}", m.robot_id(),
                          m.object_seq(), r.reason);
  } else if (r.status == AddStatus::kConflict) {
    count_refused(r, *robot, "an object report");
  } else {
    CAIRN_LOG_EVERY_N_SEC(log_, spdlog::level::info, 1.0, "{} {} from {} ({})", m.class_name(), m.object_seq(),
                          sessions_.label(*robot), to_string(r.status));
  }
  return r;
}

std::optional<RobotId> BaseNode::ingest(const cairn_msgs::RobotStatus& m, bool live, bool* news) {
  std::string error;
  auto nav = dds::nav_status_from(m, &error);
  if (nav && (m.robot_id() < 0 || m.robot_id() >= RobotSessions::kFirstRestartId)) {
    nav.reset();
    error = "robot_id out of range";
  }
  if (!nav) {
    count_rejected(m.robot_id());
    CAIRN_LOG_EVERY_N_SEC(log_, spdlog::level::warn, 2.0, "robot{}'s status: {}", m.robot_id(), error);
    return std::nullopt;
  }
  const auto robot = base_id(m.robot_id(), m.session());
  RobotLink& link = links_[*robot];
  const bool finished_news = m.finished() && !(link.has_status && link.last_status.finished());
  if (news) *news = !link.has_status || link.last_status.finished() != m.finished();
  if (finished_news) log_->info("{} reports finished{}", sessions_.label(*robot), live ? "" : " (journal)");
  link.last_status = m;
  link.has_status = true;
  note_navigation(*nav, *robot, live);
  link.last_heard_s = live ? now_s() : -1.0;  // restored: not heard since this base started
  return robot;
}

bool BaseNode::from_its_robot(const dds::GuidPrefix& writer, int32_t robot_id, const char* what) {
  if (options_.security_dir.empty()) return true;  // no certificates: nothing to check against
  if (dds::authenticated_as(writer, dds::robot_identity(robot_id))) return true;
  ++spoofed_samples_;
  CAIRN_LOG_EVERY_N_SEC(log_, spdlog::level::warn, 2.0,
                        "refused {} claiming robot{}: its writer does not hold robot{}'s certificate ({} refused)",
                        what, robot_id, robot_id, spoofed_samples_);
  return false;
}

bool BaseNode::poll_inputs() {
  bool any = false;
  // Journaled under the base's id of the robot's session (the payload keeps the robot's own).
  auto journal_key = [this](int32_t robot_id, uint32_t session) { return base_id(robot_id, session)->value; };
  for (const auto& [m, writer, received_ns] : keyframe_in_->take_all_from_writers()) {
    any = true;
    if (from_its_robot(writer, m.robot_id(), "a keyframe") && ingest(m).stored()) {
      journal(JournalKind::kKeyframe, journal_key(m.robot_id(), m.session()), m.seq(),
              dds::to_cdr<cairn_msgs::KeyframePubSubType>(m));
    }
  }
  // Keyframe poses after this poll's keyframes.
  for (const auto& [m, writer, received_ns] : keyframe_poses_in_->take_all_from_writers()) {
    any = true;
    if (from_its_robot(writer, m.robot_id(), "keyframe poses") && ingest(m).stored()) {
      journal(JournalKind::kKeyframePoses, journal_key(m.robot_id(), m.session()), 0,
              dds::to_cdr<cairn_msgs::KeyframePosesPubSubType>(m));
    }
  }
  for (const auto& [m, writer, received_ns] : object_in_->take_all_from_writers()) {
    any = true;
    if (from_its_robot(writer, m.robot_id(), "an object report") && ingest(m).stored()) {
      journal(JournalKind::kObject, journal_key(m.robot_id(), m.session()), m.object_seq(),
              dds::to_cdr<cairn_msgs::ObjectReportPubSubType>(m));
    }
  }
  for (const auto& [m, writer, received_ns] : status_in_->take_all_from_writers()) {
    if (!from_its_robot(writer, m.robot_id(), "a status")) continue;
    bool news = false;
    const auto robot = ingest(m, /*live=*/true, &news);
    if (!robot) continue;
    links_[*robot].round_trip.add(m.probe_echo_ns(), m.probe_held_ns(), uint64_t(received_ns));
    unjournaled_status_[*robot] = m;  // the newest per robot; see flush_journal()
    status_urgent_ = status_urgent_ || news;
  }
  flush_journal();
  return any;
}

}  // namespace cairn::base
