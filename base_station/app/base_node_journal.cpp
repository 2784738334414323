// BaseNode's journal: opened (or a previous mission's moved aside) at start-up, read back into the
// mapper through the same ingest path as live samples, and appended to before any ack goes out.
#include <ctime>
#include <filesystem>
#include <optional>

#include "base_station/app/base_node.h"
#include "dds/cdr.h"

namespace cairn::base {

namespace {

/// Decodes one journal record as a sample of PubSubType and hands it to `take`. False, with
/// `error` set, when it is not a whole sample or `take` refuses it.
template <typename PubSubType, typename Msg, typename Take>
bool replay(const JournalRecord& r, Take&& take, std::string* error) {
  Msg m;
  if (!dds::from_cdr<PubSubType>(r.payload, &m)) {
    *error = "not a whole sample";
    return false;
  }
  if (!take(m)) {
    *error = "refused as a sample (see the warning above)";
    return false;
  }
  return true;
}

}  // namespace

bool BaseNode::open_journal(std::string* error) {
  namespace fs = std::filesystem;
  const std::string path =
      options_.journal_path.empty() ? (fs::path(options_.out_dir) / "journal.sqlite").string() : options_.journal_path;
  std::error_code ec;
  if (options_.new_mission && fs::exists(path, ec)) {
    // Never deleted: the previous mission's journal is renamed, with its WAL and index files.
    char stamp[32];
    const std::time_t now = std::time(nullptr);
    std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", std::localtime(&now));
    std::string aside = path + "." + stamp;
    for (int n = 2; fs::exists(aside, ec); ++n) aside = path + "." + stamp + "-" + std::to_string(n);
    for (const char* suffix : {"", "-wal", "-shm"}) {
      if (fs::exists(path + suffix, ec)) fs::rename(path + suffix, aside + suffix, ec);
      if (ec) {
        *error = "cannot move the previous journal " + path + suffix + " aside: " + ec.message();
        return false;
      }
    }
    log_->info("previous mission's journal moved to {}", aside);
  }
  journal_ = Journal::open(path, JournalOptions{}, error);
  if (!journal_) return false;
  const auto contents = journal_->load(error);
  if (!contents) return false;
  restore(*contents);
  return true;
}

void BaseNode::restore(const JournalContents& contents) {
  restore_skipped_ = contents.skipped;
  auto skip = [&](const JournalRecord& r, const std::string& why) {
    restore_skipped_.push_back(std::string(to_string(r.kind)) + " " + std::to_string(r.key) + " of " +
                               to_string(r.robot) + ": " + why);
  };
  // A record is restored when it decodes and the mapper takes it as it would take a live sample.
  auto taken = [this](const auto& m) { return ingest(m).status != AddStatus::kRejected; };
  // The robots' sessions first: every sample record then resolves to the base id it had.
  for (const JournalRecord& r : contents.records) {
    if (r.kind != JournalKind::kSession) continue;
    std::string why;
    const auto s = session_record_from_json(std::string(r.payload.begin(), r.payload.end()), &why);
    if (s && sessions_.restore(*s))
      ++restored_records_;
    else
      skip(r, s ? "contradicts a session restored before" : why);
  }
  // Then the ids the team already knows the objects by, before any object is computed again.
  for (const JournalRecord& r : contents.records) {
    if (r.kind != JournalKind::kObjectId) continue;
    last_object_id_key_ = std::max(last_object_id_key_, r.key);  // a damaged record's key is not reused
    std::string why;
    const auto e = object_id_record_from_json(r.payload, &why);
    if (e && mapper_.restore_object_id(*e))
      ++restored_records_;
    else
      skip(r, e ? "contradicts the order of the ids restored before" : why);
  }
  for (const JournalRecord& r : contents.records) {
    std::string why;
    bool restored = false;
    switch (r.kind) {
      case JournalKind::kSession:
      case JournalKind::kObjectId:
        continue;  // above
      case JournalKind::kKeyframe:
        restored = replay<cairn_msgs::KeyframePubSubType, cairn_msgs::Keyframe>(r, taken, &why);
        break;
      case JournalKind::kObject:
        restored = replay<cairn_msgs::ObjectReportPubSubType, cairn_msgs::ObjectReport>(r, taken, &why);
        break;
      case JournalKind::kKeyframePoses:
        restored = replay<cairn_msgs::KeyframePosesPubSubType, cairn_msgs::KeyframePoses>(r, taken, &why);
        break;
      case JournalKind::kStatus:
        restored = replay<cairn_msgs::RobotStatusPubSubType, cairn_msgs::RobotStatus>(
            r, [this](const cairn_msgs::RobotStatus& m) { return ingest(m, /*live=*/false).has_value(); }, &why);
        break;
      case JournalKind::kCommand:
        restored = restore_command(r, &why);
        break;
      case JournalKind::kVerdict:
        restored = restore_verdict(r, &why);
        break;
      case JournalKind::kSearch:
        restored = restore_search(r, &why);
        break;
      case JournalKind::kAlertAck:
        restored = restore_alert_ack(r, &why);
        break;
      case JournalKind::kAlignment:
        restored = restore_alignment(r, &why);
        break;
    }
    if (restored)
      ++restored_records_;
    else
      skip(r, why);
  }
  after_restore_commands();
  for (const std::string& s : restore_skipped_) log_->warn("journal {}: skipped {}", journal_->path(), s);
  if (restored_records_ > 0) {
    log_->info("resumed from journal {}: {} keyframes, {} object reports of {} robots ({} records, {} skipped)",
               journal_->path(), mapper_.keyframes().size(), mapper_.object_reports().size(), mapper_.robots().size(),
               restored_records_, restore_skipped_.size());
  }
}

void BaseNode::journal(JournalKind kind, int32_t robot_id, int64_t key, std::vector<uint8_t> payload) {
  JournalRecord r;
  r.kind = kind;
  r.robot = RobotId(robot_id);
  r.key = key;
  r.payload = std::move(payload);
  unjournaled_.push_back(std::move(r));
}

void BaseNode::flush_journal() {
  // What the object-id registry learnt when the objects were last computed (for the console or an
  // export): a restarted base shows every victim under the id the team already knows.
  for (const ObjectIdRegistry::Entry& e : mapper_.take_object_id_entries()) {
    journal(JournalKind::kObjectId, 0, ++last_object_id_key_, object_id_record_to_json(e));
  }
  // Statuses arrive twice a second per robot and are never acknowledged: they ride along with the
  // next batch of samples instead of costing a commit (an fsync) each, except a robot's first one
  // and its "finished", which a restarted base must know.
  if (!unjournaled_.empty() || status_urgent_) {
    for (auto& [robot, status] : unjournaled_status_) {
      journal(JournalKind::kStatus, robot.value, 0, dds::to_cdr<cairn_msgs::RobotStatusPubSubType>(status));
    }
    unjournaled_status_.clear();
    status_urgent_ = false;
  }
  if (unjournaled_.empty()) return;
  std::string error;
  const auto t0 = std::chrono::steady_clock::now();
  const bool ok = journal_->append(unjournaled_, &error);
  journal_commit_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ++journal_commits_;
  if (ok) {
    unjournaled_.clear();
  } else {  // kept for the next try; acks wait until it succeeds
    CAIRN_LOG_EVERY_N_SEC(log_, spdlog::level::err, 5.0, "{} ({} samples wait, not acknowledged)", error,
                          unjournaled_.size());
  }
}

}  // namespace cairn::base
