// The outbox keeps what an agent produced across a restart until the base has it: earlier
// sessions come back oldest first with what is still unacknowledged, acknowledged keyframes go,
// a delivered session is forgotten, and files that are not this robot's outbox are refused untouched.
#include "robot_agent/app/outbox.h"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace cairn::agent {
namespace {

namespace fs = std::filesystem;

std::string fresh_path(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("outbox_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const fs::path p = dir / name;
  for (const char* suffix : {"", "-wal", "-shm"}) fs::remove(p.string() + suffix);
  return p.string();
}

OutboxItem item(OutboxKind kind, int32_t seq, uint8_t byte) { return OutboxItem{kind, seq, {byte, byte}}; }

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(Outbox, AnEarlierRunsUnacknowledgedRecordsComeBackAfterARestart) {
  const std::string path = fresh_path("a.sqlite");
  std::string error;
  {
    auto o = Outbox::open(path, RobotId(1), &error);
    ASSERT_TRUE(o) << error;
    ASSERT_TRUE(o->put(7, {item(OutboxKind::kKeyframe, 0, 1), item(OutboxKind::kKeyframe, 1, 2)}, &error)) << error;
    ASSERT_TRUE(o->put(7, {item(OutboxKind::kObject, 0, 3), item(OutboxKind::kKeyframe, 2, 4)}, &error)) << error;
    // A newer estimate of object 0 and the newest poses replace what was stored.
    ASSERT_TRUE(o->put(7, {item(OutboxKind::kObject, 0, 5), item(OutboxKind::kKeyframePoses, 0, 6)}, &error));
    ASSERT_TRUE(o->put(7, {item(OutboxKind::kKeyframePoses, 0, 8)}, &error));
    ASSERT_TRUE(o->acknowledged(7, 0, &error)) << error;  // the base stored keyframe 0
    EXPECT_EQ(o->held(7), 4);
  }  // the process dies here
  auto o = Outbox::open(path, RobotId(1), &error);
  ASSERT_TRUE(o) << error;
  ASSERT_TRUE(o->put(9, {item(OutboxKind::kKeyframe, 0, 9)}, &error));  // the new run's own
  const auto earlier = o->earlier_sessions(9, &error);
  ASSERT_EQ(earlier.size(), 1u) << error;
  const OutboxSession& s = earlier[0];
  EXPECT_EQ(s.session, 7u);
  EXPECT_EQ(s.last_keyframe_seq, 2);  // not lowered by the acknowledgement
  EXPECT_EQ(s.objects, 1);
  ASSERT_EQ(s.items.size(), 4u);
  EXPECT_EQ(s.items[0].kind, OutboxKind::kKeyframe);
  EXPECT_EQ(s.items[0].seq, 1);
  EXPECT_EQ(s.items[1].seq, 2);
  EXPECT_EQ(s.items[2].kind, OutboxKind::kObject);
  EXPECT_EQ(s.items[2].payload, std::vector<uint8_t>({5, 5}));
  EXPECT_EQ(s.items[3].kind, OutboxKind::kKeyframePoses);
  EXPECT_EQ(s.items[3].payload, std::vector<uint8_t>({8, 8}));
  // Delivered: forgotten, and the running session is never its own "earlier" one.
  ASSERT_TRUE(o->forget(7, &error)) << error;
  EXPECT_TRUE(o->earlier_sessions(9, &error).empty());
  EXPECT_EQ(o->held(9), 1);
}

TEST(Outbox, EarlierSessionsComeOldestFirstAndADeliveredOneIsLeftOut) {
  const std::string path = fresh_path("b.sqlite");
  std::string error;
  auto o = Outbox::open(path, RobotId(0), &error);
  ASSERT_TRUE(o) << error;
  ASSERT_TRUE(o->put(900, {item(OutboxKind::kKeyframe, 0, 1)}, &error));
  ASSERT_TRUE(o->put(5, {item(OutboxKind::kKeyframe, 0, 2)}, &error));
  ASSERT_TRUE(o->put(70, {item(OutboxKind::kKeyframe, 3, 3)}, &error));
  ASSERT_TRUE(o->acknowledged(70, 3, &error));  // everything of 70 is stored: nothing to resend
  const auto earlier = o->earlier_sessions(1, &error);
  ASSERT_EQ(earlier.size(), 2u);
  EXPECT_EQ(earlier[0].session, 900u);
  EXPECT_EQ(earlier[1].session, 5u);
}

TEST(Outbox, AFileThatIsNotThisRobotsOutboxIsRefusedUntouched) {
  std::string error;
  const std::string other = fresh_path("robot2.sqlite");
  ASSERT_TRUE(Outbox::open(other, RobotId(2), &error)) << error;
  EXPECT_FALSE(Outbox::open(other, RobotId(3), &error));
  EXPECT_NE(error.find("holds robot 2's records, this agent is robot3"), std::string::npos) << error;

  const std::string text = fresh_path("notes.txt");
  std::ofstream(text) << "not a database at all, but the operator's notes\n";
  const std::string before = read_all(text);
  EXPECT_FALSE(Outbox::open(text, RobotId(0), &error));
  EXPECT_NE(error.find("outbox " + text), std::string::npos) << error;
  EXPECT_EQ(read_all(text), before);

  const std::string journal = fresh_path("journal.sqlite");  // another application's database
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(journal.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "CREATE TABLE records (x INTEGER);", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(db);
  EXPECT_FALSE(Outbox::open(journal, RobotId(0), &error));
  EXPECT_NE(error.find("not a Cairn outbox"), std::string::npos) << error;
}

}  // namespace
}  // namespace cairn::agent
