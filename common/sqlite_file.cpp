#include "common/sqlite_file.h"

namespace cairn {

bool sqlite_exec(sqlite3* db, const std::string& sql, const std::string& what_path, std::string* error) {
  char* message = nullptr;
  if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &message) == SQLITE_OK) return true;
  if (error) *error = what_path + ": " + (message ? message : sqlite3_errmsg(db));
  sqlite3_free(message);
  return false;
}

sqlite3* open_sqlite_file(const std::string& path, const SqliteFileOptions& options, std::string* error) {
  const std::string name = options.what + " " + path;
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) != SQLITE_OK) {
    if (error) *error = name + ": " + (db ? sqlite3_errmsg(db) : "cannot open");
    sqlite3_close(db);
    return nullptr;
  }
  const auto fail = [&] {
    // close_v2: a statement still open in the caller's scope (the table check's) defers the close
    // instead of failing it (sqlite3_close returned SQLITE_BUSY and leaked the connection: found by
    // the journal's fuzz harness).
    sqlite3_close_v2(db);
    return nullptr;
  };
  sqlite3_busy_timeout(db, options.busy_timeout_ms);
  // Read before anything is written: a file that is not a database fails here, untouched.
  if (!sqlite_exec(db, "PRAGMA schema_version;", name, error)) return fail();
  // Another application's database is refused rather than given our tables.
  std::string others = "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name NOT LIKE 'sqlite_%'";
  for (size_t i = 0; i < options.tables.size(); ++i)
    others += (i == 0 ? " AND name NOT IN ('" : ", '") + options.tables[i] + "'" +
              (i + 1 == options.tables.size() ? ")" : "");
  {
    SqliteStatement s;
    sqlite3_prepare_v2(db, others.c_str(), -1, &s.stmt, nullptr);
    if (!s.stmt || sqlite3_step(s.stmt) != SQLITE_ROW) {
      if (error) *error = name + ": " + sqlite3_errmsg(db);
      return fail();
    }
    if (sqlite3_column_int64(s.stmt, 0) > 0) {
      if (error) *error = name + ": a SQLite database but not a Cairn " + options.what + " (it has other tables)";
      return fail();
    }
  }
  if (!sqlite_exec(db,
                   options.sync_full ? "PRAGMA journal_mode=WAL; PRAGMA synchronous=FULL;"
                                     : "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL;",
                   name, error) ||
      !sqlite_exec(db, options.schema, name, error)) {
    return fail();
  }
  return db;
}

}  // namespace cairn
