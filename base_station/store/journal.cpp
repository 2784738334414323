#include "base_station/store/journal.h"

#include "common/sqlite_file.h"

namespace cairn::base {

namespace {

using Statement = SqliteStatement;

bool known_kind(int64_t kind) { return kind >= 0 && kind <= int64_t(JournalKind::kAlignment); }

}  // namespace

const char* to_string(JournalKind kind) {
  switch (kind) {
    case JournalKind::kKeyframe:
      return "keyframe";
    case JournalKind::kObject:
      return "object";
    case JournalKind::kKeyframePoses:
      return "keyframe poses";
    case JournalKind::kStatus:
      return "status";
    case JournalKind::kCommand:
      return "operator command";
    case JournalKind::kVerdict:
      return "object verdict";
    case JournalKind::kSearch:
      return "search control";
    case JournalKind::kSession:
      return "robot session";
    case JournalKind::kAlertAck:
      return "alert acknowledgement";
    case JournalKind::kObjectId:
      return "object id";
    case JournalKind::kAlignment:
      return "operator alignment";
  }
  return "unknown";
}

bool Journal::exec(const char* sql, std::string* error) const {
  return sqlite_exec(db_, sql, "journal " + path_, error);
}

std::unique_ptr<Journal> Journal::open(const std::string& path, const JournalOptions& options, std::string* error) {
  SqliteFileOptions file;
  file.what = "journal";
  file.tables = {"cairn_journal_meta", "records"};
  file.schema =
      "CREATE TABLE IF NOT EXISTS cairn_journal_meta (format_version INTEGER NOT NULL);"
      "CREATE TABLE IF NOT EXISTS records ("
      "  kind INTEGER NOT NULL, robot INTEGER NOT NULL, key INTEGER NOT NULL, payload BLOB NOT NULL,"
      "  PRIMARY KEY (kind, robot, key));";
  file.sync_full = options.sync_full;
  file.busy_timeout_ms = options.busy_timeout_ms;
  sqlite3* db = open_sqlite_file(path, file, error);
  if (!db) return nullptr;
  std::unique_ptr<Journal> j(new Journal(db, path));
  Statement version;
  sqlite3_prepare_v2(db, "SELECT format_version FROM cairn_journal_meta", -1, &version.stmt, nullptr);
  const int step = version.stmt ? sqlite3_step(version.stmt) : SQLITE_ERROR;
  if (step == SQLITE_DONE) {
    const std::string insert = "INSERT INTO cairn_journal_meta VALUES (" + std::to_string(kFormatVersion) + ");";
    if (!j->exec(insert.c_str(), error)) return nullptr;
  } else if (step != SQLITE_ROW) {
    if (error) *error = "journal " + path + ": " + sqlite3_errmsg(db);
    return nullptr;
  } else if (sqlite3_column_int(version.stmt, 0) != kFormatVersion) {
    if (error) {
      *error = "journal " + path + ": format version " + std::to_string(sqlite3_column_int(version.stmt, 0)) +
               ", this base station reads " + std::to_string(kFormatVersion);
    }
    return nullptr;
  }
  return j;
}

Journal::~Journal() { sqlite3_close(db_); }

bool Journal::append(const std::vector<JournalRecord>& records, std::string* error) {
  if (records.empty()) return true;
  if (!exec("BEGIN IMMEDIATE;", error)) return false;
  Statement s;
  if (sqlite3_prepare_v2(db_, "INSERT OR REPLACE INTO records (kind, robot, key, payload) VALUES (?, ?, ?, ?)", -1,
                         &s.stmt, nullptr) != SQLITE_OK) {
    if (error) *error = "journal " + path_ + ": " + sqlite3_errmsg(db_);
    exec("ROLLBACK;", nullptr);
    return false;
  }
  for (const JournalRecord& r : records) {
    sqlite3_reset(s.stmt);
    sqlite3_bind_int(s.stmt, 1, int(r.kind));
    sqlite3_bind_int(s.stmt, 2, r.robot.value);
    sqlite3_bind_int64(s.stmt, 3, r.key);
    sqlite3_bind_blob(s.stmt, 4, r.payload.data(), int(r.payload.size()), SQLITE_STATIC);
    if (sqlite3_step(s.stmt) != SQLITE_DONE) {
      if (error) {
        *error = "journal " + path_ + ": cannot store " + to_string(r.kind) + " " + std::to_string(r.key) + " of " +
                 to_string(r.robot) + ": " + sqlite3_errmsg(db_);
      }
      exec("ROLLBACK;", nullptr);
      return false;
    }
  }
  if (!exec("COMMIT;", error)) {
    exec("ROLLBACK;", nullptr);
    return false;
  }
  return true;
}

std::optional<JournalContents> Journal::load(std::string* error) const {
  Statement s;
  if (sqlite3_prepare_v2(db_, "SELECT rowid, kind, robot, key, payload FROM records ORDER BY kind, robot, key", -1,
                         &s.stmt, nullptr) != SQLITE_OK) {
    if (error) *error = "journal " + path_ + ": " + sqlite3_errmsg(db_);
    return std::nullopt;
  }
  JournalContents out;
  int step;
  while ((step = sqlite3_step(s.stmt)) == SQLITE_ROW) {
    const int64_t row = sqlite3_column_int64(s.stmt, 0);
    const int64_t kind = sqlite3_column_int64(s.stmt, 1);
    const int64_t robot = sqlite3_column_int64(s.stmt, 2);
    if (!known_kind(kind) || robot < 0 || robot > INT32_MAX || sqlite3_column_type(s.stmt, 4) != SQLITE_BLOB) {
      out.skipped.push_back("row " + std::to_string(row) + ": kind " + std::to_string(kind) + ", robot " +
                            std::to_string(robot) + " is not a journal record");
      continue;
    }
    JournalRecord r;
    r.kind = JournalKind(kind);
    r.robot = RobotId(int32_t(robot));
    r.key = sqlite3_column_int64(s.stmt, 3);
    const auto* blob = static_cast<const uint8_t*>(sqlite3_column_blob(s.stmt, 4));
    r.payload.assign(blob, blob + sqlite3_column_bytes(s.stmt, 4));
    out.records.push_back(std::move(r));
  }
  if (step != SQLITE_DONE) {
    if (error) *error = "journal " + path_ + ": " + sqlite3_errmsg(db_);
    return std::nullopt;
  }
  return out;
}

int64_t Journal::size() const {
  Statement s;
  if (sqlite3_prepare_v2(db_, "SELECT count(*) FROM records", -1, &s.stmt, nullptr) != SQLITE_OK) return -1;
  return sqlite3_step(s.stmt) == SQLITE_ROW ? sqlite3_column_int64(s.stmt, 0) : -1;
}

}  // namespace cairn::base
