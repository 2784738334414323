#pragma once
// A SQLite file of Cairn's own (the base station's journal, an agent's outbox): opened or created
// with WAL on and its schema in place, or refused, untouched, when it is not a database or is
// another application's (it has tables outside the ones named). SQLite rather than a hand-written
// log for both: atomic batches, crash recovery and files any sqlite3 shell can inspect, for free.
#include <sqlite3.h>

#include <string>
#include <vector>

namespace cairn {

/// Finalizes a prepared statement on scope exit.
struct SqliteStatement {
  sqlite3_stmt* stmt = nullptr;
  SqliteStatement() = default;
  SqliteStatement(const SqliteStatement&) = delete;
  SqliteStatement& operator=(const SqliteStatement&) = delete;
  ~SqliteStatement() { sqlite3_finalize(stmt); }
};

struct SqliteFileOptions {
  std::string what;                 ///< "journal", "outbox": how errors name the file
  std::vector<std::string> tables;  ///< the tables it may hold
  std::string schema;               ///< CREATE TABLE IF NOT EXISTS ... for those tables
  bool sync_full = true;            ///< FULL: a commit survives a power cut; NORMAL: a crash of the process
  int busy_timeout_ms = 2000;       ///< how long a write waits for another connection's lock
};

/// The open database, or nullptr with `error` naming the file ("<what> <path>: ...").
sqlite3* open_sqlite_file(const std::string& path, const SqliteFileOptions& options, std::string* error);

/// Runs `sql`; false with `error` = "<what> <path>: <SQLite's message>".
bool sqlite_exec(sqlite3* db, const std::string& sql, const std::string& what_path, std::string* error);

}  // namespace cairn
