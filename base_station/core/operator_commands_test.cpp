#include "base_station/core/operator_commands.h"

#include <gtest/gtest.h>

#include <cmath>

namespace cairn::base {
namespace {

CommandCheckContext context() {
  CommandCheckContext c;
  c.placements[RobotId(0)] = SE2(0, 0, 0);
  c.placements[RobotId(1)] = SE2(10, 0, M_PI / 2);
  c.placements[RobotId(2)] = std::nullopt;  // not linked yet
  c.has_map = true;
  c.map_min_m = {-5, -5};
  c.map_max_m = {20, 15};
  return c;
}

CommandRequest go(std::vector<RobotId> robots, double x, double y) {
  return {std::move(robots), CommandKind::kGoTo, {x, y}};
}

TEST(CheckCommand, AGotoInsideTheMapToAPlacedRobotMayGo) {
  EXPECT_EQ(check_command(go({RobotId(1)}, 3, 4), context()), std::nullopt);
  EXPECT_EQ(check_command({{RobotId(2)}, CommandKind::kStop, {0, 0}}, context()), std::nullopt);
}

TEST(CheckCommand, BadRequestsAreRefusedWithTheReason) {
  auto why = [](const CommandRequest& r, const CommandCheckContext& c = context()) {
    return check_command(r, c).value_or("(accepted)");
  };
  EXPECT_NE(why(go({RobotId(7)}, 1, 1)).find("unknown robot 7"), std::string::npos);
  EXPECT_NE(why(go({RobotId(2)}, 1, 1)).find("not placed on the map yet"), std::string::npos);
  EXPECT_NE(why(go({RobotId(0)}, NAN, 1)).find("not a finite number"), std::string::npos);
  EXPECT_NE(why(go({RobotId(0)}, 1, INFINITY)).find("not a finite number"), std::string::npos);
  EXPECT_NE(why(go({RobotId(0)}, 40, 1)).find("outside the map"), std::string::npos);
  EXPECT_NE(why(go({}, 1, 1)).find("no robot"), std::string::npos);
  CommandCheckContext restarted = context();
  restarted.ended_sessions[RobotId(1)] = RobotId(1001);  // robot 1 restarted: its old session ended
  EXPECT_NE(why({{RobotId(1)}, CommandKind::kStop, {0, 0}}, restarted).find("session that ended"), std::string::npos);
  EXPECT_NE(why({{RobotId(1)}, CommandKind::kStop, {0, 0}}, restarted).find("command 1001"), std::string::npos);
  CommandCheckContext no_map = context();
  no_map.has_map = false;
  EXPECT_NE(why(go({RobotId(0)}, 1, 1), no_map).find("no map yet"), std::string::npos);
  // The operator's own search controls: no goto into a keep-out area, no resume while paused.
  CommandCheckContext controlled = context();
  controlled.keep_out.push_back({4, {2, 2}, {5, 6}});
  EXPECT_EQ(why(go({RobotId(0)}, 3, 3), controlled), "the point is in keep-out area 4");
  EXPECT_EQ(why(go({RobotId(0)}, 6, 3), controlled), "(accepted)");
  controlled.exploration_paused = true;
  EXPECT_NE(why({{RobotId(0)}, CommandKind::kResume, {0, 0}}, controlled).find("exploration is paused"),
            std::string::npos);
  EXPECT_EQ(why({{RobotId(0)}, CommandKind::kHome, {0, 0}}, controlled), "(accepted)");
}

TEST(CommandBook, AGotoIsSentInTheRobotsOwnFrameAndFollowsItsReports) {
  CommandBook book;
  const OperatorCommand sent = book.add(1, RobotId(1), CommandKind::kGoTo, {10, 5}, SE2(10, 0, M_PI / 2), 100);
  // Robot 1 entered at (10, 0) facing +y: the global point (10, 5) is 5 m straight ahead of it.
  EXPECT_NEAR(sent.goal_m.x(), 5, 1e-9);
  EXPECT_NEAR(sent.goal_m.y(), 0, 1e-9);
  EXPECT_EQ(sent.seq, 1u);
  EXPECT_EQ(book.records()[0].state, CommandState::kSent);
  EXPECT_TRUE(book.under_operator(RobotId(1)));
  EXPECT_TRUE(book.on_report(RobotId(1), {1, CommandState::kActive, "driving"}));
  EXPECT_FALSE(book.on_report(RobotId(1), {1, CommandState::kActive, "driving"}));  // nothing new
  EXPECT_FALSE(book.on_report(RobotId(0), {1, CommandState::kDone, ""}));           // another robot's word
  EXPECT_TRUE(book.on_report(RobotId(1), {1, CommandState::kDone, "reached"}));
  EXPECT_EQ(book.records()[0].state, CommandState::kDone);
}

TEST(CommandBook, ACommandTheRobotNeverCarriedOutIsReportedOvertaken) {
  CommandBook book;
  book.add(1, RobotId(0), CommandKind::kGoTo, {1, 1}, SE2(), 0);
  book.add(2, RobotId(1), CommandKind::kStop, {0, 0}, std::nullopt, 0);
  book.add(3, RobotId(0), CommandKind::kStop, {0, 0}, SE2(), 0);
  EXPECT_TRUE(book.on_report(RobotId(0), {3, CommandState::kDone, "stopped"}));
  EXPECT_EQ(book.records()[0].state, CommandState::kOvertaken);
  EXPECT_NE(book.records()[0].note.find("command 3"), std::string::npos);
  EXPECT_EQ(book.records()[1].state, CommandState::kSent);  // robot 1's is not touched
  EXPECT_EQ(book.records()[2].state, CommandState::kDone);
  book.add(4, RobotId(0), CommandKind::kResume, {0, 0}, SE2(), 0);
  EXPECT_FALSE(book.under_operator(RobotId(0)));
  EXPECT_TRUE(book.under_operator(RobotId(1)));
  EXPECT_FALSE(book.under_operator(RobotId(5)));
}

TEST(CommandBook, RestoredCommandsKeepTheirOrderAndTheNextSeqFollowsThem) {
  CommandBook book;
  book.restore({RobotId(0), 7, CommandKind::kStop, {0, 0}}, {0, 0}, 50);
  book.restore({RobotId(1), 3, CommandKind::kGoTo, {2, 2}}, {4, 4}, 10);
  book.restore({RobotId(1), 3, CommandKind::kGoTo, {2, 2}}, {4, 4}, 10);  // twice: once kept
  ASSERT_EQ(book.records().size(), 2u);
  EXPECT_EQ(book.records()[0].seq, 3u);
  EXPECT_EQ(book.last_seq(), 7u);
  EXPECT_DEATH(book.add(5, RobotId(0), CommandKind::kStop, {0, 0}, SE2(), 0), "seq 5 after 7");
}

}  // namespace
}  // namespace cairn::base
