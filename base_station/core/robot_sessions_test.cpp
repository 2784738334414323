#include "base_station/core/robot_sessions.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace cairn::base {
namespace {

TEST(RobotSessions, ARestartedRobotIsANewRobotAndOnlyItsNewestSessionIsCurrent) {
  RobotSessions s;
  bool is_new = false;
  EXPECT_EQ(s.resolve(RobotId(1), 0xabcu, &is_new), RobotId(1));  // the first session keeps the robot's id
  EXPECT_TRUE(is_new);
  EXPECT_EQ(s.resolve(RobotId(1), 0xabcu, &is_new), RobotId(1));
  EXPECT_FALSE(is_new);
  EXPECT_EQ(s.resolve(RobotId(2), 0xabcu), RobotId(2));  // another robot may draw the same session id
  const RobotId restarted = s.resolve(RobotId(1), 0x123u, &is_new);
  EXPECT_TRUE(is_new);
  EXPECT_EQ(restarted, RobotId(RobotSessions::kFirstRestartId));
  EXPECT_FALSE(s.is_current(RobotId(1)));
  EXPECT_TRUE(s.is_current(restarted));
  EXPECT_TRUE(s.is_current(RobotId(2)));
  EXPECT_TRUE(s.is_current(RobotId(7)));  // never heard of
  EXPECT_EQ(s.current(RobotId(1)), restarted);
  EXPECT_EQ(s.current(RobotId(7)), RobotId(7));
  // A late sample of the old session still goes to the old session's robot.
  EXPECT_EQ(s.resolve(RobotId(1), 0xabcu), RobotId(1));
  EXPECT_TRUE(s.is_current(restarted));
  EXPECT_EQ(s.label(RobotId(1)), "robot1");
  EXPECT_EQ(s.label(restarted), "robot1 session 2");
  ASSERT_EQ(s.restarts().size(), 1u);
  EXPECT_EQ(s.restarts()[0].robot, RobotId(1));
  EXPECT_EQ(s.restarts()[0].ordinal, 2);
  EXPECT_EQ(s.resolve(RobotId(2), 0x77u), RobotId(RobotSessions::kFirstRestartId + 1));
  EXPECT_THROW(s.resolve(RobotId(RobotSessions::kFirstRestartId), 1u), std::invalid_argument);
  EXPECT_THROW(s.resolve(RobotId(-1), 1u), std::invalid_argument);
}

TEST(RobotSessions, RestoredSessionsGiveTheSameIdsAndContradictionsAreRefused) {
  RobotSessions live;
  live.resolve(RobotId(0), 5u);
  const RobotId second = live.resolve(RobotId(0), 9u);
  RobotSessions restored;
  // Restored in any order, they give the ids the live base gave, and new sessions continue after them.
  ASSERT_TRUE(restored.restore(*live.find(second)));
  ASSERT_TRUE(restored.restore(*live.find(RobotId(0))));
  EXPECT_TRUE(restored.restore(*live.find(second)));  // the same again is no contradiction
  EXPECT_EQ(restored.resolve(RobotId(0), 5u), RobotId(0));
  EXPECT_EQ(restored.resolve(RobotId(0), 9u), second);
  EXPECT_TRUE(restored.is_current(second));
  EXPECT_EQ(restored.resolve(RobotId(3), 1u), RobotId(3));
  EXPECT_EQ(restored.resolve(RobotId(3), 2u).value, second.value + 1);
  // Contradictions: another session under a known id, a known session under another id, an
  // ordinal that does not fit the id.
  EXPECT_FALSE(restored.restore({second, RobotId(0), 11u, 2}));
  EXPECT_FALSE(restored.restore({RobotId(1500), RobotId(0), 9u, 3}));
  EXPECT_FALSE(restored.restore({RobotId(4), RobotId(4), 1u, 2}));
  EXPECT_FALSE(restored.restore({RobotId(1600), RobotId(5), 1u, 1}));
  EXPECT_FALSE(restored.restore({RobotId(4), RobotId(-4), 1u, 1}));
  // Through the journal's JSON and back; a damaged record names what is wrong.
  std::string error;
  const auto back = session_record_from_json(session_record_to_json(*live.find(second)), &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->base_id, second);
  EXPECT_EQ(back->session, 9u);
  EXPECT_EQ(back->ordinal, 2);
  EXPECT_FALSE(session_record_from_json(R"({"base_id": 1001, "robot": 0, "session": -1, "ordinal": 2})", &error));
  EXPECT_NE(error.find("\"session\""), std::string::npos) << error;
  EXPECT_FALSE(session_record_from_json(R"({"base_id": 1001, "robot": 5000, "session": 1, "ordinal": 2})", &error));
  EXPECT_FALSE(session_record_from_json("[1, 2]", &error));
}

}  // namespace
}  // namespace cairn::base
