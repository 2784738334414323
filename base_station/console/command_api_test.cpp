#include "base_station/console/command_api.h"

#include <gtest/gtest.h>

#include "common/random_token.h"

namespace cairn::base {
namespace {

const std::vector<RobotId> kRobots = {RobotId(1), RobotId(2)};

std::string parse_error(const std::string& body) {
  std::string error;
  EXPECT_FALSE(parse_command_request(body, kRobots, &error).has_value()) << body;
  return error;
}

TEST(OperatorToken, MatchesOnlyTheExactBearerToken) {
  EXPECT_TRUE(operator_token_matches("Bearer abc123", "abc123"));
  EXPECT_FALSE(operator_token_matches("Bearer abc124", "abc123"));
  EXPECT_FALSE(operator_token_matches("Bearer abc1234", "abc123"));
  EXPECT_FALSE(operator_token_matches("abc123", "abc123"));
  EXPECT_FALSE(operator_token_matches("Basic abc123", "abc123"));
  EXPECT_FALSE(operator_token_matches("Bearer ", ""));  // an empty token never opens the door
}

TEST(OperatorToken, GeneratedTokensAreLongAndDiffer) {
  const std::string a = random_hex_token();
  const std::string b = random_hex_token();
  EXPECT_EQ(a.size(), 32u);
  EXPECT_NE(a, b);
}

TEST(ParseCommandRequest, ReadsGoToAndAll) {
  std::string error;
  const auto go = parse_command_request(R"({"robot": 2, "kind": "goto", "x_m": 3.5, "y_m": -1})", kRobots, &error);
  ASSERT_TRUE(go.has_value()) << error;
  EXPECT_EQ(go->kind, CommandKind::kGoTo);
  ASSERT_EQ(go->robots.size(), 1u);
  EXPECT_EQ(go->robots[0], RobotId(2));
  EXPECT_DOUBLE_EQ(go->point_global_m.x(), 3.5);
  EXPECT_DOUBLE_EQ(go->point_global_m.y(), -1.0);

  const auto stop = parse_command_request(R"({"robot": "all", "kind": "stop"})", kRobots, &error);
  ASSERT_TRUE(stop.has_value()) << error;
  EXPECT_EQ(stop->kind, CommandKind::kStop);
  EXPECT_EQ(stop->robots, kRobots);
}

TEST(ParseCommandRequest, NamesWhatIsWrong) {
  EXPECT_NE(parse_error("{oops").find("not JSON"), std::string::npos);
  EXPECT_NE(parse_error("[1,2]").find("object"), std::string::npos);
  EXPECT_NE(parse_error(R"({"robot": 1})").find("kind"), std::string::npos);
  EXPECT_NE(parse_error(R"({"robot": 1, "kind": "fly"})").find("fly"), std::string::npos);
  EXPECT_NE(parse_error(R"({"kind": "stop"})").find("robot"), std::string::npos);
  EXPECT_NE(parse_error(R"({"robot": -3, "kind": "stop"})").find("robot"), std::string::npos);
  EXPECT_NE(parse_error(R"({"robot": "two", "kind": "stop"})").find("robot"), std::string::npos);
  EXPECT_NE(parse_error(R"({"robot": 1, "kind": "goto", "y_m": 1})").find("x_m"), std::string::npos);
  // JSON cannot carry NaN: a browser sends null for it.
  EXPECT_NE(parse_error(R"({"robot": 1, "kind": "goto", "x_m": 1, "y_m": null})").find("y_m"), std::string::npos);
}

TEST(CommandInbox, GivesOneSequenceNumberPerRobotAndContinuesAfterRestart) {
  CommandInbox inbox;
  inbox.start_after(41);
  CommandRequest all;
  all.kind = CommandKind::kStop;
  all.robots = kRobots;
  EXPECT_EQ(inbox.push(all), (std::vector<uint32_t>{42, 43}));
  const auto taken = inbox.take_all();
  ASSERT_EQ(taken.size(), 2u);
  EXPECT_EQ(taken[0].robot, RobotId(1));
  EXPECT_EQ(taken[1].seq, 43u);
  EXPECT_TRUE(inbox.take_all().empty());
  inbox.start_after(10);  // never goes backwards
  EXPECT_EQ(inbox.push(all).front(), 44u);
}

}  // namespace
}  // namespace cairn::base
