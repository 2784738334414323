#pragma once
// The base station's journal: every sample it stored, in SQLite, written before the sample is
// acknowledged to its robot, and read back when the base restarts, so a crash or a power cut of
// the base loses nothing a robot was told is safe (even if that robot is gone by then).
// Records are opaque bytes (the app stores DDS samples as CDR); one record per (kind, robot, key):
// a newer keyframe-poses estimate, object report or status replaces the older one.
// SQLite rather than a hand-written log: atomic batches, crash recovery and a file any sqlite3
// shell can inspect, for free.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/ids.h"

struct sqlite3;

namespace cairn::base {

/// Replay order on load: a keyframe before the objects anchored on it and the poses that move it.
/// kCommand: an operator's command as sent (JSON), keyed by its sequence number; kVerdict: the
/// operator's verdict on an object (JSON), keyed by the object's robot and seq; kSearch: the
/// operator's pause, resume or keep-out area (JSON), keyed by its sequence number (robot 0);
/// kSession: a robot's session (JSON, base_station/core/robot_sessions.h), under its base id and
/// keyed by the session id (restored before everything else); kObjectId: a fact of the object-id
/// registry (JSON, base_station/core/object_id_registry.h), keyed 1, 2, ... (restored next);
/// kAlignment: the operator's latest alignment of a robot's map (JSON), under that robot, key 0.
enum class JournalKind : int32_t {
  kKeyframe = 0,
  kObject = 1,
  kKeyframePoses = 2,
  kStatus = 3,
  kCommand = 4,
  kVerdict = 5,
  kSearch = 6,
  kSession = 7,
  kAlertAck = 8,
  kObjectId = 9,
  kAlignment = 10
};
const char* to_string(JournalKind kind);

struct JournalRecord {
  JournalKind kind = JournalKind::kKeyframe;
  RobotId robot;
  int64_t key = 0;  ///< keyframe seq, object seq; 0 for one-per-robot kinds
  std::vector<uint8_t> payload;
};

struct JournalOptions {
  /// FULL: a committed batch survives a power cut (WAL mode; one fsync a batch). NORMAL survives
  /// a crash of the process only.
  bool sync_full = true;
  /// How long a write waits for another connection's lock (e.g. an operator's sqlite3 shell).
  int busy_timeout_ms = 2000;
};

struct JournalContents {
  std::vector<JournalRecord> records;  ///< in replay order: kind, robot, key
  std::vector<std::string> skipped;    ///< rows that could not be read, each named ("row 12: ...")
};

class Journal {
 public:
  /// Opens or creates the journal at `path`. nullptr with `error` naming the file when it is not
  /// a Cairn journal (another SQLite file, a newer format, not a database); the file is left as is.
  static std::unique_ptr<Journal> open(const std::string& path, const JournalOptions& options, std::string* error);
  ~Journal();
  Journal(const Journal&) = delete;
  Journal& operator=(const Journal&) = delete;

  /// Stores all `records` in one transaction, or none of them (false, `error` set).
  bool append(const std::vector<JournalRecord>& records, std::string* error);
  /// Everything stored; nullopt with `error` set when the file cannot be read at all.
  std::optional<JournalContents> load(std::string* error) const;
  /// Number of records stored.
  int64_t size() const;
  const std::string& path() const { return path_; }

  static constexpr int kFormatVersion = 1;

 private:
  Journal(sqlite3* db, std::string path) : db_(db), path_(std::move(path)) {}
  bool exec(const char* sql, std::string* error) const;
  sqlite3* db_;
  std::string path_;
};

}  // namespace cairn::base
