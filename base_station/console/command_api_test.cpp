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

TEST(CommandRecordJson, RoundTripsAndNamesWhatIsWrong) {
  CommandRecord r;
  r.seq = 12;
  r.robot = RobotId(3);
  r.kind = CommandKind::kGoTo;
  r.point_global_m = {4.5, -2.25};
  r.point_local_m = {1.0, 0.5};
  r.sent_ns = 123456789012;
  std::string error;
  const auto back = command_record_from_json(command_record_to_json(r), &error);
  ASSERT_TRUE(back.has_value()) << error;
  EXPECT_EQ(back->seq, 12u);
  EXPECT_EQ(back->robot, RobotId(3));
  EXPECT_EQ(back->kind, CommandKind::kGoTo);
  EXPECT_EQ(back->point_global_m, r.point_global_m);
  EXPECT_EQ(back->point_local_m, r.point_local_m);
  EXPECT_EQ(back->sent_ns, r.sent_ns);

  nlohmann::json j = nlohmann::json::parse(command_record_to_json(r));
  const auto fault = [&](nlohmann::json bad) {
    std::string why;
    EXPECT_FALSE(command_record_from_json(bad.dump(), &why).has_value()) << bad.dump();
    return why;
  };
  EXPECT_NE(fault(nlohmann::json::array()).find("object"), std::string::npos);
  auto bad = j;
  bad["seq"] = 0;
  EXPECT_NE(fault(bad).find("seq"), std::string::npos);
  bad = j;
  bad["kind"] = 9;
  EXPECT_NE(fault(bad).find("kind"), std::string::npos);
  bad = j;
  bad["global_m"] = {1.0};
  EXPECT_NE(fault(bad).find("global_m"), std::string::npos);
  bad = j;
  bad.erase("sent_ns");
  EXPECT_NE(fault(bad).find("sent_ns"), std::string::npos);
  EXPECT_FALSE(command_record_from_json("{truncated", &error).has_value());
}

TEST(VerdictRecordJson, RoundTripsAndNamesWhatIsWrong) {
  const VerdictRecord r{{RobotId(2), 7}, ObjectVerdict::kFalse, "a mannequin", 99};
  std::string error;
  const auto back = verdict_record_from_json(verdict_record_to_json(r), &error);
  ASSERT_TRUE(back.has_value()) << error;
  EXPECT_EQ(back->object, r.object);
  EXPECT_EQ(back->verdict, ObjectVerdict::kFalse);
  EXPECT_EQ(back->note, "a mannequin");
  EXPECT_EQ(back->at_ns, 99);
  EXPECT_FALSE(verdict_record_from_json("[]", &error).has_value());
  EXPECT_FALSE(
      verdict_record_from_json(R"({"robot": 2, "seq": 7, "verdict": "perhaps", "note": "", "at_ns": 1})", &error)
          .has_value());
  EXPECT_NE(error.find("verdict"), std::string::npos) << error;
  EXPECT_FALSE(
      verdict_record_from_json(R"({"robot": -1, "seq": 7, "verdict": "false", "note": "", "at_ns": 1})", &error)
          .has_value());
}

}  // namespace
}  // namespace cairn::base
