#include "base_station/console/console_server.h"
#include "base_station/core/multi_robot_mapper.h"

#include <gtest/gtest.h>
#include <httplib.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "base_station/core/synthetic_world_test_util.h"
#include "base_station/core/unlinked_robot_test_util.h"

namespace cairn::base {
namespace {

MultiRobotMapper make_mapper() {
  MultiRobotMapper mapper;
  mapper.set_robot_start(RobotId(0), testing::left_path()[0]);
  for (const Keyframe& kf : testing::make_keyframes(RobotId(0), testing::left_path(), testing::room_walls())) {
    mapper.add_keyframe(kf);
  }
  for (const Keyframe& kf : testing::make_keyframes(RobotId(3), testing::right_path(), testing::room_walls())) {
    mapper.add_keyframe(kf);
  }
  mapper.add_object(testing::make_object({RobotId(0), 2}, "victim", {4.3, 3.5, 0.2}, 3, testing::left_path()[3]));
  mapper.optimize();
  return mapper;
}

TEST(Snapshot, DescribesRobotsObjectsAndAlerts) {
  const MultiRobotMapper mapper = make_mapper();
  const ConsoleSnapshot s =
      make_snapshot(mapper.merged(), {{"0", {{"state", "ok"}, {"bytes_rx", 1234}, {"pose_local", {1.0, 0.5, 0.25}}}},
                                      {"3", {{"pose_local", {1.0, 0.5, 0.25}}}}});
  ASSERT_EQ(s.robots.size(), 2u);
  EXPECT_EQ(s.robots[0]["linked"], true);
  EXPECT_EQ(s.robots[0]["trajectory"].size(), 6u);
  EXPECT_EQ(s.robots[0]["link"]["bytes_rx"], 1234);
  EXPECT_EQ(s.robots[1]["linked"], false);
  // A placed robot's newest pose on the map; an unplaced one has none (its frame is not placed).
  ASSERT_EQ(s.robots[0]["pose_m"].size(), 3u);
  const SE2 expected = mapper.merged().robots[0].T_global_local * SE2(1.0, 0.5, 0.25);
  EXPECT_NEAR(s.robots[0]["pose_m"][0].get<double>(), expected.x(), 1e-9);
  EXPECT_NEAR(s.robots[0]["pose_m"][1].get<double>(), expected.y(), 1e-9);
  EXPECT_TRUE(s.robots[1]["pose_m"].is_null());
  ASSERT_EQ(s.objects.size(), 1u);
  EXPECT_EQ(s.objects[0]["id"], "0-2");
  EXPECT_EQ(s.objects[0]["thumbnail"], "/api/objects/0-2/thumbnail.jpg?v=5");
  EXPECT_EQ(s.status["alerts"][0]["level"], "critical");
  EXPECT_NE(s.status["alerts"][0]["text"].get<std::string>().find("Victim found by robot 0"), std::string::npos);
  EXPECT_EQ(s.status["alerts"].size(), 2u);  // + robot 3 not linked
  EXPECT_EQ(s.status["alerts"][0]["key"], "object:0-2");
  // Out of contact for 10 s or more, and stuck, from the robots' links.
  const ConsoleSnapshot lost = make_snapshot(mapper.merged(), {{"0",
                                                                {{"state", "lost"},
                                                                 {"last_heard_age_s", 12.5},
                                                                 {"nav_state", "stuck"},
                                                                 {"collision_risk", true},
                                                                 {"pose_local", {500.0, 0.0, 0.0}}}},
                                                               {"3", {{"state", "stale"}, {"last_heard_age_s", 4.0}}}});
  std::vector<std::string> keys;
  for (const auto& a : lost.status["alerts"]) keys.push_back(a["key"]);
  EXPECT_NE(std::find(keys.begin(), keys.end(), "contact:0"), keys.end());
  EXPECT_NE(std::find(keys.begin(), keys.end(), "stuck:0"), keys.end());
  EXPECT_NE(std::find(keys.begin(), keys.end(), "collision:0"), keys.end());
  EXPECT_NE(std::find(keys.begin(), keys.end(), "left:0"), keys.end()) << "500 m away is off the map";
  std::vector<std::string> calm;  // the first snapshot: on the map, no collision risk
  for (const auto& a : s.status["alerts"]) calm.push_back(a["key"]);
  EXPECT_EQ(std::find(calm.begin(), calm.end(), "left:0"), calm.end());
  EXPECT_EQ(std::find(keys.begin(), keys.end(), "contact:3"), keys.end()) << "stale for 4 s is not lost";
  EXPECT_GT(s.map_png.size(), 8u);
  EXPECT_LE(s.clouds.at("0-2").size(), 2000u);
}

TEST(Snapshot, ShowsWhereEachRobotShouldSearchNext) {
  const MultiRobotMapper mapper = make_mapper();
  ExplorationPlan plan;
  plan.frontiers.push_back({{6.0, 1.0}, 30, 1.5, 1.0});
  plan.goals.push_back({RobotId(0), 0, {6.0, 1.0}, 4.2, 0.3});
  plan.idle.push_back(RobotId(3));
  plan.meetings.push_back({RobotId(2), RobotId(0), {4.0, 2.5}});  // active linking
  const ConsoleSnapshot s = make_snapshot(mapper.merged(), nlohmann::json::object(), {}, &plan);
  const nlohmann::json& e = s.status["exploration"];
  EXPECT_EQ(e["frontiers"], 1);
  ASSERT_EQ(e["goals"].size(), 1u);
  EXPECT_EQ(e["goals"][0]["robot"], 0);
  EXPECT_DOUBLE_EQ(e["goals"][0]["x_m"].get<double>(), 6.0);
  EXPECT_DOUBLE_EQ(e["goals"][0]["path_m"].get<double>(), 4.2);
  EXPECT_DOUBLE_EQ(e["goals"][0]["frontier_m"].get<double>(), 1.5);
  EXPECT_EQ(e["idle"], nlohmann::json::array({3}));
  ASSERT_EQ(e["meetings"].size(), 1u);
  EXPECT_EQ(e["meetings"][0]["robot"], 2);
  EXPECT_EQ(e["meetings"][0]["teammate"], 0);
  EXPECT_DOUBLE_EQ(e["meetings"][0]["y_m"].get<double>(), 2.5);
  // The map view's layers: the frontier where it is, and the known part of the map to show first.
  ASSERT_EQ(s.layers["frontiers"].size(), 1u);
  EXPECT_DOUBLE_EQ(s.layers["frontiers"][0]["x_m"].get<double>(), 6.0);
  ASSERT_EQ(s.layers["bounds_m"].size(), 2u);
  EXPECT_LT(s.layers["bounds_m"][0][0].get<double>(), s.layers["bounds_m"][1][0].get<double>());
  EXPECT_GT(s.grid_cells.width, 0);
  // The goal is drawn on the map; without a plan there is no "exploration" entry.
  const ConsoleSnapshot without = make_snapshot(mapper.merged(), nlohmann::json::object());
  EXPECT_FALSE(without.status.contains("exploration"));
  EXPECT_NE(s.map_png, without.map_png);
}

TEST(Snapshot, AnUnlinkedRobotsVictimIsInTheApiTheAlertsAndItsOwnMap) {
  const testing::UnlinkableRobot u;
  const ConsoleSnapshot s = make_snapshot(u.mapper.merged(), nlohmann::json::object());
  EXPECT_EQ(s.status["unlinked_robots"], nlohmann::json::array({1}));
  EXPECT_EQ(s.status["unplaced_objects"], 1);
  ASSERT_EQ(s.objects.size(), 1u);
  const nlohmann::json& o = s.objects[0];
  EXPECT_EQ(o["id"], "1-0");
  EXPECT_EQ(o["frame"], "robot1");
  EXPECT_NEAR(o["position_m"][0].get<double>(), 4.0, 0.05);
  EXPECT_NE(o["from_entry"]["text"].get<std::string>().find("from where robot 1 entered"), std::string::npos);
  bool alerted = false;
  for (const auto& a : s.status["alerts"]) {
    if (a.value("object", "") == "1-0") {
      alerted = true;
      EXPECT_EQ(a["level"], "critical");
      EXPECT_EQ(a["frame"], "robot1");
      EXPECT_NE(a["text"].get<std::string>().find("not on the map yet"), std::string::npos) << a["text"];
    }
  }
  EXPECT_TRUE(alerted) << s.status["alerts"].dump();
  ASSERT_TRUE(s.own_maps.count("1"));
  EXPECT_EQ(std::string(s.own_maps.at("1").begin(), s.own_maps.at("1").begin() + 8),
            std::string("\x89PNG\r\n\x1a\n", 8));
  for (const auto& r : s.robots) {
    if (r["id"] == 1) {
      EXPECT_EQ(r["own_map"], "/api/robots/1/own_map.png");
      EXPECT_TRUE(r["time_to_link_s"].is_null());
    }
  }
}

TEST(ConsoleServer, ServesPagesAndApi) {
  LatestSnapshot latest;
  latest.publish(make_snapshot(make_mapper().merged(), nlohmann::json::object()));
  ConsoleServer server({"127.0.0.1", 0, ""}, [&latest] { return latest.get(); });
  std::string error;
  ASSERT_TRUE(server.start(&error)) << error;
  ASSERT_GT(server.port(), 0);
  httplib::Client client("127.0.0.1", server.port());
  client.set_connection_timeout(5);

  auto index = client.Get("/");
  ASSERT_TRUE(index);
  EXPECT_EQ(index->status, 200);
  EXPECT_NE(index->body.find("<html"), std::string::npos);
  for (const char* path : {"/app.js", "/common.js", "/control.js", "/style.css", "/report.html", "/report.js"}) {
    auto r = client.Get(path);
    ASSERT_TRUE(r) << path;
    EXPECT_EQ(r->status, 200) << path;
  }
  auto status = client.Get("/api/status");
  ASSERT_TRUE(status);
  EXPECT_EQ(status->status, 200);
  EXPECT_EQ(nlohmann::json::parse(status->body)["objects"], 1);
  auto robots = client.Get("/api/robots");
  ASSERT_TRUE(robots);
  EXPECT_EQ(nlohmann::json::parse(robots->body).size(), 2u);
  auto objects = client.Get("/api/objects");
  ASSERT_TRUE(objects);
  EXPECT_EQ(nlohmann::json::parse(objects->body)[0]["class"], "victim");
  auto map = client.Get("/api/map.png");
  ASSERT_TRUE(map);
  EXPECT_EQ(map->status, 200);
  ASSERT_GT(map->body.size(), 8u);
  EXPECT_EQ(map->body.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  const auto geometry = nlohmann::json::parse(map->get_header_value("X-Map-Image"), nullptr, false);
  ASSERT_TRUE(geometry.is_object()) << map->get_header_value("X-Map-Image");
  EXPECT_TRUE(geometry["valid"].get<bool>());
  EXPECT_GT(geometry["m_per_px"].get<double>(), 0.0);
  auto thumb = client.Get("/api/objects/0-2/thumbnail.jpg");
  ASSERT_TRUE(thumb);
  EXPECT_EQ(thumb->status, 200);
  EXPECT_EQ(uint8_t(thumb->body[0]), 0xFF);
  auto cloud = client.Get("/api/objects/0-2/cloud");
  ASSERT_TRUE(cloud);
  EXPECT_GT(nlohmann::json::parse(cloud->body).size(), 0u);
  auto no_own_map = client.Get("/api/robots/0/own_map.png");  // robot 0 is placed: no own map
  ASSERT_TRUE(no_own_map);
  EXPECT_EQ(no_own_map->status, 404);
  auto missing = client.Get("/api/objects/9-9/cloud");
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->status, 404);
  server.stop();
  EXPECT_FALSE(server.running());
}

TEST(ConsoleServer, ExportsAreOfferedOnceWrittenAndNothingElseIsServed) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("cairn_console_exports_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "objects.csv") << "id,class\n0-1,victim\n";
  std::ofstream(dir / "journal.sqlite") << "not for download";
  ConsoleServer server({"127.0.0.1", 0, ""}, [] { return ConsoleSnapshot{}; });
  std::string error;
  ASSERT_TRUE(server.start(&error)) << error;
  httplib::Client client("127.0.0.1", server.port());
  auto before = client.Get("/api/exports");
  ASSERT_TRUE(before);
  const auto none = nlohmann::json::parse(before->body);
  EXPECT_FALSE(none["ready"].get<bool>());
  EXPECT_TRUE(none["files"].empty());
  EXPECT_EQ(client.Get("/exports/objects.csv")->status, 404);  // not offered yet

  server.offer_exports(dir.string());
  const auto list = nlohmann::json::parse(client.Get("/api/exports")->body);
  EXPECT_TRUE(list["ready"].get<bool>());
  ASSERT_EQ(list["files"].size(), 1u) << list.dump();  // not the journal
  EXPECT_EQ(list["files"][0]["name"], "objects.csv");
  auto csv = client.Get("/exports/objects.csv");
  ASSERT_TRUE(csv);
  EXPECT_EQ(csv->status, 200);
  EXPECT_EQ(csv->body, "id,class\n0-1,victim\n");
  EXPECT_NE(csv->get_header_value("Content-Disposition").find("objects.csv"), std::string::npos);
  EXPECT_EQ(client.Get("/exports/journal.sqlite")->status, 404);
  EXPECT_EQ(client.Get("/exports/..%2Fetc%2Fpasswd")->status, 404);
  EXPECT_EQ(client.Get("/exports/missing.csv")->status, 404);
  server.stop();
  fs::remove_all(dir);
}

TEST(ConsoleServer, AStopRightAfterTheStartEnds) {
  // A mission that ends at once stops the console right after starting it; httplib ignores a stop
  // before its listening loop runs, which used to leave the join waiting forever.
  for (int i = 0; i < 50; ++i) {
    ConsoleServer server({"127.0.0.1", 0, ""}, [] { return ConsoleSnapshot{}; });
    std::string error;
    ASSERT_TRUE(server.start(&error)) << error;
    server.stop();
    EXPECT_FALSE(server.running());
  }
}

TEST(ConsoleServer, CopyingProviderAndEmptySnapshot) {
  ConsoleServer server({"127.0.0.1", 0, ""}, [] { return ConsoleSnapshot{}; });
  std::string error;
  ASSERT_TRUE(server.start(&error)) << error;
  httplib::Client client("127.0.0.1", server.port());
  auto status = client.Get("/api/status");
  ASSERT_TRUE(status);
  EXPECT_EQ(status->status, 200);
  auto map = client.Get("/api/map.png");
  ASSERT_TRUE(map);
  EXPECT_EQ(map->status, 404);
}

}  // namespace
}  // namespace cairn::base
