#include "robot_agent/app/outbox.h"

#include "common/sqlite_file.h"

#include <algorithm>

namespace cairn::agent {

namespace {

using Statement = SqliteStatement;

}  // namespace

bool Outbox::exec(const std::string& sql, std::string* error) const {
  return sqlite_exec(db_, sql, "outbox " + path_, error);
}

std::unique_ptr<Outbox> Outbox::open(const std::string& path, RobotId robot, std::string* error) {
  SqliteFileOptions file;
  file.what = "outbox";
  file.tables = {"cairn_outbox_meta", "sessions", "items"};
  file.schema =
      "CREATE TABLE IF NOT EXISTS cairn_outbox_meta (format_version INTEGER NOT NULL, robot INTEGER NOT NULL);"
      "CREATE TABLE IF NOT EXISTS sessions ("
      "  session INTEGER PRIMARY KEY, started INTEGER NOT NULL, last_keyframe_seq INTEGER NOT NULL);"
      "CREATE TABLE IF NOT EXISTS items ("
      "  session INTEGER NOT NULL, kind INTEGER NOT NULL, seq INTEGER NOT NULL, payload BLOB NOT NULL,"
      "  PRIMARY KEY (session, kind, seq));";
  // NORMAL: a committed record survives the process being killed; a power cut may take the last
  // ones (FULL would fsync at every keyframe).
  file.sync_full = false;
  sqlite3* db = open_sqlite_file(path, file, error);
  if (!db) return nullptr;
  std::unique_ptr<Outbox> o(new Outbox(db, path));
  Statement meta;
  sqlite3_prepare_v2(db, "SELECT format_version, robot FROM cairn_outbox_meta", -1, &meta.stmt, nullptr);
  const int step = meta.stmt ? sqlite3_step(meta.stmt) : SQLITE_ERROR;
  if (step == SQLITE_DONE) {
    if (!o->exec("INSERT INTO cairn_outbox_meta VALUES (" + std::to_string(kFormatVersion) + ", " +
                     std::to_string(robot.value) + ");",
                 error))
      return nullptr;
  } else if (step != SQLITE_ROW) {
    if (error) *error = "outbox " + path + ": " + sqlite3_errmsg(db);
    return nullptr;
  } else if (sqlite3_column_int(meta.stmt, 0) != kFormatVersion) {
    if (error) {
      *error = "outbox " + path + ": format version " + std::to_string(sqlite3_column_int(meta.stmt, 0)) +
               ", this agent reads " + std::to_string(kFormatVersion);
    }
    return nullptr;
  } else if (sqlite3_column_int(meta.stmt, 1) != robot.value) {
    if (error) {
      *error = "outbox " + path + ": it holds robot " + std::to_string(sqlite3_column_int(meta.stmt, 1)) +
               "'s records, this agent is " + to_string(robot);
    }
    return nullptr;
  }
  return o;
}

Outbox::~Outbox() { sqlite3_close(db_); }

std::vector<OutboxSession> Outbox::earlier_sessions(uint32_t running, std::string* error) const {
  std::vector<OutboxSession> out;
  Statement sessions;
  if (sqlite3_prepare_v2(db_, "SELECT session, last_keyframe_seq FROM sessions WHERE session != ? ORDER BY started", -1,
                         &sessions.stmt, nullptr) != SQLITE_OK) {
    if (error) *error = "outbox " + path_ + ": " + sqlite3_errmsg(db_);
    return {};
  }
  sqlite3_bind_int64(sessions.stmt, 1, running);
  Statement items;
  sqlite3_prepare_v2(db_, "SELECT kind, seq, payload FROM items WHERE session = ? ORDER BY kind, seq", -1, &items.stmt,
                     nullptr);
  while (sqlite3_step(sessions.stmt) == SQLITE_ROW) {
    OutboxSession s;
    s.session = uint32_t(sqlite3_column_int64(sessions.stmt, 0));
    s.last_keyframe_seq = sqlite3_column_int(sessions.stmt, 1);
    sqlite3_reset(items.stmt);
    sqlite3_bind_int64(items.stmt, 1, s.session);
    while (sqlite3_step(items.stmt) == SQLITE_ROW) {
      const int kind = sqlite3_column_int(items.stmt, 0);
      if (kind < 0 || kind > int(OutboxKind::kKeyframePoses)) continue;  // not ours: never sent
      OutboxItem item;
      item.kind = OutboxKind(kind);
      item.seq = sqlite3_column_int(items.stmt, 1);
      const auto* bytes = static_cast<const uint8_t*>(sqlite3_column_blob(items.stmt, 2));
      item.payload.assign(bytes, bytes + sqlite3_column_bytes(items.stmt, 2));
      s.objects += item.kind == OutboxKind::kObject;  // object records stay until the session is forgotten
      s.items.push_back(std::move(item));
    }
    // A session with nothing left was delivered (the run ended before it was forgotten).
    if (!s.items.empty()) out.push_back(std::move(s));
  }
  return out;
}

bool Outbox::put(uint32_t session, const std::vector<OutboxItem>& items, std::string* error) {
  if (items.empty()) return true;
  int32_t last_seq = -1;
  for (const OutboxItem& item : items)
    if (item.kind == OutboxKind::kKeyframe) last_seq = std::max(last_seq, item.seq);
  if (!exec("BEGIN IMMEDIATE;", error)) return false;
  const std::string s = std::to_string(session);
  const std::string l = std::to_string(last_seq);
  if (!exec("INSERT INTO sessions VALUES (" + s + ", (SELECT coalesce(max(started), 0) + 1 FROM sessions), " + l +
                ") ON CONFLICT(session) DO UPDATE SET last_keyframe_seq = max(last_keyframe_seq, " + l + ");",
            error)) {
    exec("ROLLBACK;", nullptr);
    return false;
  }
  Statement insert;
  sqlite3_prepare_v2(db_, "INSERT OR REPLACE INTO items (session, kind, seq, payload) VALUES (?, ?, ?, ?)", -1,
                     &insert.stmt, nullptr);
  for (const OutboxItem& item : items) {
    sqlite3_reset(insert.stmt);
    sqlite3_bind_int64(insert.stmt, 1, session);
    sqlite3_bind_int(insert.stmt, 2, int(item.kind));
    sqlite3_bind_int(insert.stmt, 3, item.seq);
    sqlite3_bind_blob(insert.stmt, 4, item.payload.data(), int(item.payload.size()), SQLITE_STATIC);
    if (!insert.stmt || sqlite3_step(insert.stmt) != SQLITE_DONE) {
      if (error)
        *error = "outbox " + path_ + ": cannot store record " + std::to_string(item.seq) + ": " + sqlite3_errmsg(db_);
      exec("ROLLBACK;", nullptr);
      return false;
    }
  }
  if (exec("COMMIT;", error)) return true;
  exec("ROLLBACK;", nullptr);
  return false;
}

bool Outbox::acknowledged(uint32_t session, int32_t keyframe_seq, std::string* error) {
  return exec("DELETE FROM items WHERE session = " + std::to_string(session) + " AND kind = " +
                  std::to_string(int(OutboxKind::kKeyframe)) + " AND seq <= " + std::to_string(keyframe_seq) + ";",
              error);
}

bool Outbox::forget(uint32_t session, std::string* error) {
  const std::string s = std::to_string(session);
  if (exec("BEGIN IMMEDIATE; DELETE FROM items WHERE session = " + s + "; DELETE FROM sessions WHERE session = " + s +
               "; COMMIT;",
           error))
    return true;
  exec("ROLLBACK;", nullptr);
  return false;
}

int64_t Outbox::held(uint32_t session) const {
  Statement s;
  sqlite3_prepare_v2(db_, "SELECT count(*) FROM items WHERE session = ?", -1, &s.stmt, nullptr);
  sqlite3_bind_int64(s.stmt, 1, session);
  return s.stmt && sqlite3_step(s.stmt) == SQLITE_ROW ? sqlite3_column_int64(s.stmt, 0) : -1;
}

}  // namespace cairn::agent
