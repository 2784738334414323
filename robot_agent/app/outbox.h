#pragma once
// The agent's outbox on disk: every keyframe, object report and keyframe-poses estimate the agent
// produces, kept in SQLite until the base station acknowledges it. A robot that reboots (a crash,
// a power cut, a watchdog) while the radio is down or slow would otherwise lose all it had not
// delivered; restarted with the same outbox, the agent resends that earlier run's records under
// the earlier run's session id (the base keeps each session apart: base_station/core/robot_sessions.h)
// before its new session speaks. Records are opaque bytes (the agent stores DDS samples as CDR).
// SQLite, as the base's journal, for atomic batches and crash recovery (WAL) for free.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/ids.h"

struct sqlite3;

namespace cairn::agent {

enum class OutboxKind : int32_t { kKeyframe = 0, kObject = 1, kKeyframePoses = 2 };

struct OutboxItem {
  OutboxKind kind = OutboxKind::kKeyframe;
  int32_t seq = 0;  ///< keyframe seq, object seq; 0 for keyframe poses (one per session)
  std::vector<uint8_t> payload;
};

/// What one session still holds: the records not acknowledged yet and how far it got.
struct OutboxSession {
  uint32_t session = 0;
  int32_t last_keyframe_seq = -1;  ///< the highest keyframe seq it produced (-1: none)
  int32_t objects = 0;             ///< distinct objects it reported
  std::vector<OutboxItem> items;   ///< keyframes by seq, then objects, then the poses
};

class Outbox {
 public:
  /// Opens or creates `robot`'s outbox at `path`. nullptr with `error` naming the file when it is
  /// not a Cairn outbox (another database, not a database) or belongs to another robot; the file
  /// is then left as it is.
  static std::unique_ptr<Outbox> open(const std::string& path, RobotId robot, std::string* error);
  ~Outbox();
  Outbox(const Outbox&) = delete;
  Outbox& operator=(const Outbox&) = delete;

  /// The sessions of earlier runs that still hold records, oldest first (`running` left out).
  std::vector<OutboxSession> earlier_sessions(uint32_t running, std::string* error) const;
  /// Stores `items` of `session` in one transaction (a record with the same kind and seq is
  /// replaced: an object's newer estimate, the newest poses); the session is created when new.
  bool put(uint32_t session, const std::vector<OutboxItem>& items, std::string* error);
  /// The base stored `session`'s keyframes up to `keyframe_seq`: they are deleted.
  bool acknowledged(uint32_t session, int32_t keyframe_seq, std::string* error);
  /// The base has all of `session`: its records and the session are deleted.
  bool forget(uint32_t session, std::string* error);
  /// Records held for `session` (all kinds).
  int64_t held(uint32_t session) const;
  const std::string& path() const { return path_; }

  static constexpr int kFormatVersion = 1;

 private:
  Outbox(sqlite3* db, std::string path) : db_(db), path_(std::move(path)) {}
  bool exec(const std::string& sql, std::string* error) const;
  sqlite3* db_;
  std::string path_;
};

}  // namespace cairn::agent
