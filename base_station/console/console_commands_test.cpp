// POST /api/commands (and the verdict, alignment and alert routes) end to end through the HTTP
// server: who may command, and every bad request refused with a message and nothing queued.
// Eigen (through console_server.h) before httplib.h: <resolv.h>'s _res macro breaks Eigen's headers.
#include "base_station/console/console_server.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <chrono>
#include <thread>

namespace cairn::base {
namespace {

const char* kToken = "0123456789abcdef0123456789abcdef";

ConsoleSnapshot snapshot_with_two_robots() {
  ConsoleSnapshot s;
  s.command_context.placements = {{RobotId(0), SE2(1.0, 2.0, M_PI / 2)}, {RobotId(3), std::nullopt}};
  s.command_context.has_map = true;
  s.command_context.map_min_m = {-1, -1};
  s.command_context.map_max_m = {10, 8};
  s.objects = nlohmann::json::array({{{"id", "0-2"}, {"aliases", {"1-0"}}}});
  s.robots = nlohmann::json::array({{{"id", 0}, {"linked", true}}, {{"id", 3}, {"linked", false}}});
  s.status = {{"alerts", nlohmann::json::array({{{"key", "object:0-2"}, {"text", "Victim found"}}})}};
  s.alert_log = nlohmann::json::array({{{"key", "object:0-2"}, {"text", "Victim found"}}});
  return s;
}

class ConsoleCommands : public ::testing::Test {
 protected:
  void SetUp() override {
    latest_.publish(snapshot_with_two_robots());
    server_ = std::make_unique<ConsoleServer>(ConsoleOptions{"127.0.0.1", 0, ""},
                                              ConsoleServer::SharedProvider([this] { return latest_.get(); }));
    server_->accept_commands(kToken, &inbox_);
    std::string error;
    ASSERT_TRUE(server_->start(&error)) << error;
    client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    client_->set_connection_timeout(5);
  }
  void TearDown() override { server_->stop(); }

  /// Status and error message of a POST with `authorization` (empty: no header).
  std::pair<int, std::string> post(const std::string& body, const std::string& authorization,
                                   const std::string& path = "/api/commands") {
    httplib::Headers headers;
    if (!authorization.empty()) headers.emplace("Authorization", authorization);
    const auto res = client_->Post(path, headers, body, "application/json");
    if (!res) return {-1, "no answer"};
    const auto j = nlohmann::json::parse(res->body, nullptr, false);
    return {res->status, j.is_object() && j.contains("error") ? j["error"].get<std::string>() : res->body};
  }
  std::pair<int, std::string> post(const std::string& body) { return post(body, std::string("Bearer ") + kToken); }

  LatestSnapshot latest_;
  CommandInbox inbox_;
  std::unique_ptr<ConsoleServer> server_;
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(ConsoleCommands, SearchControlsNeedTheTokenAndNameEveryFault) {
  const std::string bearer = std::string("Bearer ") + kToken;
  auto search = [&](const std::string& body, const std::string& auth) { return post(body, auth, "/api/search"); };
  EXPECT_EQ(search(R"({"action": "pause"})", "").first, 401);
  EXPECT_EQ(search("{", bearer), std::make_pair(400, std::string("the body is not JSON")));
  EXPECT_EQ(search(R"({"action": "nap"})", bearer).second,
            "unknown action \"nap\" (pause, resume, keep_out, clear_keep_out)");
  EXPECT_EQ(search(R"({"action": "keep_out", "area_m": [1, 2, null, 4]})", bearer).second,
            "\"area_m\" must be four numbers [x0, y0, x1, y1] (metres, map frame) for keep_out");
  EXPECT_EQ(search(R"({"action": "clear_keep_out"})", bearer).second,
            "\"area\" must be a keep-out area's id for clear_keep_out");
  EXPECT_EQ(search(R"({"action": "resume"})", bearer), std::make_pair(409, std::string("exploration is not paused")));
  EXPECT_TRUE(inbox_.take_search().empty()) << "nothing refused is queued";
  EXPECT_EQ(search(R"({"action": "keep_out", "area_m": [4, 5, 2, 3]})", bearer).first, 202);
  const std::vector<SearchControlRequest> queued = inbox_.take_search();
  ASSERT_EQ(queued.size(), 1u);
  EXPECT_EQ(queued[0].corner_a_m, Eigen::Vector2d(4, 5));
  // Once the base has applied the area, a goto into it is refused and GET /api/search lists it.
  SearchControls applied;
  applied.apply(queued[0], {}, 0);
  inbox_.post_search(applied);
  EXPECT_EQ(post(R"({"robot": 0, "kind": "goto", "x_m": 3, "y_m": 4})"),
            std::make_pair(400, std::string("the point is in keep-out area 1")));
  const auto state = nlohmann::json::parse(client_->Get("/api/search")->body);
  EXPECT_EQ(state["paused"], false);
  ASSERT_EQ(state["keep_out"].size(), 1u);
  EXPECT_EQ(state["keep_out"][0]["min_m"], nlohmann::json::array({2.0, 3.0}));
}

TEST_F(ConsoleCommands, WithoutTheTokenNothingIsQueued) {
  const std::string stop = R"({"robot": 0, "kind": "stop"})";
  EXPECT_EQ(post(stop, "").first, 401);
  EXPECT_EQ(post(stop, "Bearer wrong").first, 401);
  EXPECT_EQ(post(stop, kToken).first, 401);  // the token without "Bearer "
  EXPECT_TRUE(inbox_.take_all().empty());
}

TEST_F(ConsoleCommands, BadRequestsAreRefusedWithTheirFaultNamedAndNothingQueued) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{not json", "not JSON"},
      {R"({"robot": 0, "kind": "dance"})", "unknown kind"},
      {R"({"robot": 7, "kind": "stop"})", "unknown robot 7"},
      {R"({"robot": 3, "kind": "goto", "x_m": 1, "y_m": 1})", "not placed"},
      {R"({"robot": 0, "kind": "goto", "x_m": null, "y_m": 1})", "x_m"},
      {R"({"robot": 0, "kind": "goto", "x_m": 1e308, "y_m": 1e308})", "outside the map"},
      {R"({"robot": 0, "kind": "goto", "x_m": 30, "y_m": 1})", "outside the map"},
  };
  for (const auto& [body, fault] : cases) {
    const auto [status, message] = post(body);
    EXPECT_EQ(status, 400) << body;
    EXPECT_NE(message.find(fault), std::string::npos) << body << " -> " << message;
  }
  EXPECT_TRUE(inbox_.take_all().empty());
}

TEST_F(ConsoleCommands, AGoodCommandIsQueuedWithItsSequenceNumbers) {
  const auto go = client_->Post("/api/commands", {{"Authorization", std::string("Bearer ") + kToken}},
                                R"({"robot": 0, "kind": "goto", "x_m": 4.5, "y_m": 3})", "application/json");
  ASSERT_TRUE(go);
  EXPECT_EQ(go->status, 202);
  EXPECT_EQ(nlohmann::json::parse(go->body)["seqs"], nlohmann::json::array({1}));
  const auto all = post(R"({"robot": "all", "kind": "home"})");  // every robot, placed or not
  EXPECT_EQ(all.first, 202) << all.second;
  const auto queued = inbox_.take_all();
  ASSERT_EQ(queued.size(), 3u);
  EXPECT_EQ(queued[0].request.kind, CommandKind::kGoTo);
  EXPECT_DOUBLE_EQ(queued[0].request.point_global_m.x(), 4.5);
  EXPECT_EQ(queued[1].robot, RobotId(0));
  EXPECT_EQ(queued[2].robot, RobotId(3));
  EXPECT_EQ(queued[2].seq, 3u);
  // The list of commands, as the base posted it, is open to every viewer.
  inbox_.post_states(nlohmann::json::array({{{"seq", 4}, {"robot", 0}, {"kind", "stop"}, {"state", "done"}}}));
  const auto list = client_->Get("/api/commands");
  ASSERT_TRUE(list);
  EXPECT_EQ(nlohmann::json::parse(list->body)[0]["state"], "done");
}

TEST_F(ConsoleCommands, VerdictsNeedTheTokenAKnownObjectAndAKnownWord) {
  const auto verdict = [&](const std::string& key, const std::string& body, const std::string& auth) {
    httplib::Headers headers;
    if (!auth.empty()) headers.emplace("Authorization", auth);
    const auto res = client_->Post("/api/objects/" + key + "/verdict", headers, body, "application/json");
    return std::make_pair(res ? res->status : -1, res ? res->body : std::string());
  };
  const std::string bearer = std::string("Bearer ") + kToken;
  EXPECT_EQ(verdict("0-2", R"({"verdict": "confirmed"})", "").first, 401);
  EXPECT_EQ(verdict("5-5", R"({"verdict": "confirmed"})", bearer).first, 404);
  const auto bad = verdict("0-2", R"({"verdict": "maybe"})", bearer);
  EXPECT_EQ(bad.first, 400);
  EXPECT_NE(bad.second.find("unknown verdict"), std::string::npos) << bad.second;
  EXPECT_EQ(verdict("0-2", R"({"verdict": "false", "note": 7})", bearer).first, 400);
  EXPECT_EQ(verdict("0-2", nlohmann::json{{"verdict", "false"}, {"note", std::string(201, 'x')}}.dump(), bearer).first,
            400);
  EXPECT_TRUE(inbox_.take_verdicts().empty());
  EXPECT_EQ(verdict("0-2", R"({"verdict": "confirmed", "note": "alive"})", bearer).first, 202);
  EXPECT_EQ(verdict("1-0", R"({"verdict": "false"})", bearer).first, 202);  // the id it was first shown under
  const auto taken = inbox_.take_verdicts();
  ASSERT_EQ(taken.size(), 2u);
  EXPECT_EQ(taken[0].object, (ObjectId{RobotId(0), 2}));
  EXPECT_EQ(taken[0].verdict, ObjectVerdict::kConfirmed);
  EXPECT_EQ(taken[0].note, "alive");
  EXPECT_EQ(taken[1].object, (ObjectId{RobotId(1), 0}));
}

TEST_F(ConsoleCommands, AnAlignmentNeedsTheTokenAnUnlinkedRobotAndThreeNumbers) {
  const std::string good = R"({"x_m": 4.5, "y_m": -1.0, "yaw_deg": 90})";
  EXPECT_EQ(post(good, "", "/api/robots/3/align").first, 401);
  const std::string bearer = std::string("Bearer ") + kToken;
  EXPECT_EQ(post(good, bearer, "/api/robots/7/align").first, 404);
  const auto placed = post(good, bearer, "/api/robots/0/align");
  EXPECT_EQ(placed.first, 409);
  EXPECT_NE(placed.second.find("already on the map"), std::string::npos) << placed.second;
  for (const char* bad : {R"({"x_m": 4.5, "y_m": -1.0})", R"({"x_m": "4.5", "y_m": -1.0, "yaw_deg": 90})",
                          R"({"x_m": null, "y_m": -1.0, "yaw_deg": 90})", R"({"x_m": 1e9, "y_m": -1.0, "yaw_deg": 90})",
                          "[1, 2, 3]", "not json"}) {
    const auto r = post(bad, bearer, "/api/robots/3/align");
    EXPECT_EQ(r.first, 400) << bad;
    EXPECT_FALSE(r.second.empty()) << bad;
  }
  EXPECT_NE(post(R"({"x_m": 4.5, "y_m": -1.0})", bearer, "/api/robots/3/align").second.find("yaw_deg"),
            std::string::npos);
  EXPECT_TRUE(inbox_.take_alignments().empty()) << "a refused request queued nothing";
  EXPECT_EQ(post(good, bearer, "/api/robots/3/align").first, 202);
  const auto taken = inbox_.take_alignments();
  ASSERT_EQ(taken.size(), 1u);
  EXPECT_EQ(taken[0].robot, RobotId(3));
  EXPECT_NEAR(taken[0].T_global_local.x(), 4.5, 1e-12);
  EXPECT_NEAR(taken[0].T_global_local.yaw(), M_PI / 2, 1e-12);
  // As the base journals it, and back.
  std::string error;
  const auto again = alignment_request_from_json(alignment_request_to_json(taken[0]), &error);
  ASSERT_TRUE(again) << error;
  EXPECT_EQ(again->robot, RobotId(3));
  EXPECT_NEAR(again->T_global_local.y(), -1.0, 1e-12);
  EXPECT_FALSE(alignment_request_from_json(R"({"x_m": 1, "y_m": 2, "yaw_deg": 3})", &error));
  EXPECT_NE(error.find("robot"), std::string::npos) << error;
}

TEST_F(ConsoleCommands, TheEventStreamSaysAtOnceThatTheCommandsChanged) {
  std::string stream;
  int events = 0;
  EXPECT_EQ(server_->open_streams(), 0);
  int listening = 0;
  std::thread poster([this, &listening] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    listening = server_->open_streams();  // the base makes quick snapshots only for a listening page
    inbox_.post_states(nlohmann::json::array({{{"seq", 1}, {"state", "active"}}}));
  });
  client_->set_read_timeout(5, 0);  // nothing pushed: the stream stays silent and this gives up
  client_->Get("/api/events", [&](const char* data, size_t length) {
    stream.append(data, length);
    events = 0;
    for (size_t at = stream.find("data: "); at != std::string::npos; at = stream.find("data: ", at + 1)) ++events;
    return events < 2;  // the first event (at once), then the change
  });
  poster.join();
  ASSERT_EQ(events, 2) << stream;
  EXPECT_NE(stream.find(R"("commands":0)"), std::string::npos) << stream;
  EXPECT_NE(stream.find(R"("commands":1)"), std::string::npos) << stream;
  EXPECT_EQ(listening, 1);
}

TEST_F(ConsoleCommands, AnAlertIsAcknowledgedWithTheTokenAndShowsAtOnce) {
  const std::string bearer = std::string("Bearer ") + kToken;
  EXPECT_EQ(post(R"({"key": "object:0-2"})", "").first, 401);  // (the commands route; same check below)
  const auto ack = [&](const std::string& body, const std::string& auth) {
    httplib::Headers headers;
    if (!auth.empty()) headers.emplace("Authorization", auth);
    const auto res = client_->Post("/api/alerts/ack", headers, body, "application/json");
    return res ? res->status : -1;
  };
  EXPECT_EQ(ack(R"({"key": "object:0-2"})", ""), 401);
  EXPECT_EQ(ack(R"({"key": "contact:9"})", bearer), 404);
  EXPECT_EQ(ack(R"({"nope": 1})", bearer), 400);
  EXPECT_TRUE(inbox_.acked_alerts().empty());
  EXPECT_EQ(ack(R"({"key": "object:0-2"})", bearer), 202);
  EXPECT_EQ(inbox_.acked_alerts(), (std::set<std::string>{"object:0-2"}));
  const auto status = nlohmann::json::parse(client_->Get("/api/status")->body);
  EXPECT_TRUE(status["alerts"][0]["acked"].get<bool>()) << status.dump();
  EXPECT_EQ(nlohmann::json::parse(client_->Get("/api/alerts/log")->body).size(), 1u);
}

TEST(ConsoleCommandsOff, WithoutAnOperatorTokenCommandsAreOff) {
  ConsoleServer server({"127.0.0.1", 0, ""}, [] { return ConsoleSnapshot{}; });
  std::string error;
  ASSERT_TRUE(server.start(&error)) << error;
  httplib::Client client("127.0.0.1", server.port());
  const auto res = client.Post("/api/commands", {{"Authorization", "Bearer x"}}, R"({"robot": 0, "kind": "stop"})",
                               "application/json");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 403);
  EXPECT_NE(res->body.find("without an operator token"), std::string::npos);
}

}  // namespace
}  // namespace cairn::base
