// BaseNode's journal: opened (or a previous mission's moved aside) at start-up, read back into the
// mapper through the same ingest path as live samples, and appended to before any ack goes out.
#include <ctime>
#include <filesystem>

#include "base_station/app/base_node.h"
#include "dds/cdr.h"

namespace cairn::base {

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
    const std::string aside = path + "." + stamp;
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
  auto skip = [&](const JournalRecord& r) {
    restore_skipped_.push_back(std::string(to_string(r.kind)) + " " + std::to_string(r.key) + " of " +
                               to_string(r.robot) + ": not a whole sample");
  };
  for (const JournalRecord& r : contents.records) {
    bool ok = false;
    switch (r.kind) {
      case JournalKind::kKeyframe: {
        cairn_msgs::Keyframe m;
        if ((ok = dds::from_cdr<cairn_msgs::KeyframePubSubType>(r.payload, &m))) ingest(m);
        break;
      }
      case JournalKind::kObject: {
        cairn_msgs::ObjectReport m;
        if ((ok = dds::from_cdr<cairn_msgs::ObjectReportPubSubType>(r.payload, &m))) ingest(m);
        break;
      }
      case JournalKind::kKeyframePoses: {
        cairn_msgs::KeyframePoses m;
        if ((ok = dds::from_cdr<cairn_msgs::KeyframePosesPubSubType>(r.payload, &m))) ingest(m);
        break;
      }
      case JournalKind::kStatus: {
        cairn_msgs::RobotStatus m;
        if ((ok = dds::from_cdr<cairn_msgs::RobotStatusPubSubType>(r.payload, &m))) ingest(m, /*live=*/false);
        break;
      }
    }
    if (ok) ++restored_records_;
    else skip(r);
  }
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
