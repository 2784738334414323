// The journal keeps what it was given across reopening, replaces per (kind, robot, key), replays
// in dependency order, and refuses files that are not its own without touching them.
#include "base_station/store/journal.h"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace cairn::base {
namespace {

namespace fs = std::filesystem;

std::string fresh_path(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("journal_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const fs::path p = dir / name;
  fs::remove(p);
  fs::remove(p.string() + "-wal");
  fs::remove(p.string() + "-shm");
  return p.string();
}

JournalRecord record(JournalKind kind, int robot, int64_t key, std::vector<uint8_t> payload) {
  JournalRecord r;
  r.kind = kind;
  r.robot = RobotId(robot);
  r.key = key;
  r.payload = std::move(payload);
  return r;
}

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(Journal, KeepsRecordsAcrossReopeningInReplayOrder) {
  const std::string path = fresh_path("a.sqlite");
  std::string error;
  {
    auto j = Journal::open(path, {}, &error);
    ASSERT_TRUE(j) << error;
    ASSERT_TRUE(j->append({record(JournalKind::kStatus, 1, 0, {9}), record(JournalKind::kKeyframe, 1, 1, {1, 1}),
                           record(JournalKind::kObject, 0, 0, {7})},
                          &error))
        << error;
    ASSERT_TRUE(
        j->append({record(JournalKind::kKeyframe, 1, 0, {1, 0}), record(JournalKind::kKeyframe, 0, 0, {0})}, &error))
        << error;
    EXPECT_EQ(j->size(), 5);
  }
  auto j = Journal::open(path, {}, &error);
  ASSERT_TRUE(j) << error;
  const auto contents = j->load(&error);
  ASSERT_TRUE(contents) << error;
  EXPECT_TRUE(contents->skipped.empty());
  ASSERT_EQ(contents->records.size(), 5u);
  // Keyframes first (robot, seq), then objects, then statuses.
  const std::vector<std::tuple<JournalKind, int, int64_t>> order{{JournalKind::kKeyframe, 0, 0},
                                                                 {JournalKind::kKeyframe, 1, 0},
                                                                 {JournalKind::kKeyframe, 1, 1},
                                                                 {JournalKind::kObject, 0, 0},
                                                                 {JournalKind::kStatus, 1, 0}};
  for (size_t i = 0; i < order.size(); ++i) {
    const auto& r = contents->records[i];
    EXPECT_EQ(std::make_tuple(r.kind, r.robot.value, r.key), order[i]) << i;
  }
  EXPECT_EQ(contents->records[2].payload, (std::vector<uint8_t>{1, 1}));
}

TEST(Journal, ANewerRecordOfTheSameKeyReplacesTheOlder) {
  const std::string path = fresh_path("b.sqlite");
  std::string error;
  auto j = Journal::open(path, {}, &error);
  ASSERT_TRUE(j) << error;
  ASSERT_TRUE(j->append({record(JournalKind::kKeyframePoses, 2, 0, {1})}, &error));
  ASSERT_TRUE(j->append({record(JournalKind::kKeyframePoses, 2, 0, {2, 2})}, &error));
  const auto contents = j->load(&error);
  ASSERT_TRUE(contents) << error;
  ASSERT_EQ(contents->records.size(), 1u);
  EXPECT_EQ(contents->records[0].payload, (std::vector<uint8_t>{2, 2}));
}

TEST(Journal, AFileThatIsNotADatabaseIsRefusedAndLeftAsItWas) {
  const std::string path = fresh_path("not_a_db.sqlite");
  const std::string text(4096, 'x');
  std::ofstream(path, std::ios::binary) << text;
  std::string error;
  EXPECT_EQ(Journal::open(path, {}, &error), nullptr);
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_NE(error.find("not a database"), std::string::npos) << error;
  EXPECT_EQ(read_all(path), text);
}

TEST(Journal, AnotherApplicationsDatabaseIsRefused) {
  const std::string path = fresh_path("other.sqlite");
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "CREATE TABLE survivors (name TEXT); INSERT INTO survivors VALUES ('a');", nullptr,
                         nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  const std::string before = read_all(path);
  std::string error;
  EXPECT_EQ(Journal::open(path, {}, &error), nullptr);
  EXPECT_NE(error.find("not a Cairn journal"), std::string::npos) << error;
  EXPECT_EQ(read_all(path), before);
}

TEST(Journal, ANewerFormatIsRefusedWithBothVersions) {
  const std::string path = fresh_path("newer.sqlite");
  std::string error;
  ASSERT_TRUE(Journal::open(path, {}, &error)) << error;
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "UPDATE cairn_journal_meta SET format_version = 7;", nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  EXPECT_EQ(Journal::open(path, {}, &error), nullptr);
  EXPECT_NE(error.find("format version 7, this base station reads 1"), std::string::npos) << error;
}

TEST(Journal, RowsThatAreNotRecordsAreSkippedAndNamed) {
  const std::string path = fresh_path("bad_rows.sqlite");
  std::string error;
  {
    auto j = Journal::open(path, {}, &error);
    ASSERT_TRUE(j) << error;
    ASSERT_TRUE(j->append({record(JournalKind::kKeyframe, 0, 0, {1})}, &error));
  }
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(
      sqlite3_exec(db, "INSERT INTO records VALUES (42, 0, 0, x'00'); INSERT INTO records VALUES (0, 0, 1, 'text');",
                   nullptr, nullptr, nullptr),
      SQLITE_OK);
  sqlite3_close(db);
  auto j = Journal::open(path, {}, &error);
  ASSERT_TRUE(j) << error;
  const auto contents = j->load(&error);
  ASSERT_TRUE(contents) << error;
  EXPECT_EQ(contents->records.size(), 1u);
  ASSERT_EQ(contents->skipped.size(), 2u);
  EXPECT_NE(contents->skipped[0].find("kind 0"), std::string::npos) << contents->skipped[0];
  EXPECT_NE(contents->skipped[1].find("kind 42"), std::string::npos) << contents->skipped[1];
}

TEST(Journal, AFailedBatchStoresNothingOfIt) {
  const std::string path = fresh_path("locked.sqlite");
  std::string error;
  JournalOptions options;
  options.busy_timeout_ms = 10;
  auto j = Journal::open(path, options, &error);
  ASSERT_TRUE(j) << error;
  ASSERT_TRUE(j->append({record(JournalKind::kKeyframe, 0, 0, {1})}, &error));
  // A second connection holds the write lock: the batch cannot commit and must leave no trace.
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "BEGIN IMMEDIATE;", nullptr, nullptr, nullptr), SQLITE_OK);
  EXPECT_FALSE(j->append({record(JournalKind::kKeyframe, 0, 1, {2})}, &error));
  EXPECT_NE(error.find(path), std::string::npos) << error;
  sqlite3_exec(db, "ROLLBACK;", nullptr, nullptr, nullptr);
  sqlite3_close(db);
  EXPECT_EQ(j->size(), 1);
}

}  // namespace
}  // namespace cairn::base
