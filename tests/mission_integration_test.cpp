// End to end over real Fast DDS: the simulator, two agents and the base station run as separate
// processes (cairn_mission) on a private domain; the merged results are checked against the
// simulator's ground truth with explicit bounds.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "common/trajectory.h"
#include "common/yaml_config.h"
#include "dds/domain_lease.h"
#include "run_command.h"
#include "tools/eval/mission_eval.h"

namespace cairn::test {
namespace {

namespace fs = std::filesystem;

struct Pgm {
  int width = 0, height = 0;
  std::vector<uint8_t> pixels;  ///< top row first
  uint8_t at(int col, int row_from_bottom) const { return pixels[size_t(height - 1 - row_from_bottom) * width + col]; }
};

Pgm read_pgm(const std::string& path) {
  Pgm p;
  std::ifstream in(path, std::ios::binary);
  std::string magic;
  in >> magic;
  auto skip_comments = [&] {
    in >> std::ws;
    while (in.peek() == '#') {
      std::string line;
      std::getline(in, line);
      in >> std::ws;
    }
  };
  skip_comments();
  int maxval = 0;
  in >> p.width;
  skip_comments();
  in >> p.height;
  skip_comments();
  in >> maxval;
  in.get();
  if (magic != "P5" || maxval != 255) return {};
  p.pixels.resize(size_t(p.width) * p.height);
  in.read(reinterpret_cast<char*>(p.pixels.data()), std::streamsize(p.pixels.size()));
  return p;
}

/// The ids objects.csv names each object by, its own and its aliases ("1-0", "0-2", ...).
std::set<std::string> object_ids_in(const fs::path& csv) {
  std::set<std::string> ids;
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);  // header: id,class,...,frame,aliases,...
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream fields(line);
    for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
    if (cells.size() < 13) continue;
    ids.insert(cells[0]);
    std::stringstream aliases(cells[12]);
    for (std::string a; std::getline(aliases, a, ';');) ids.insert(a);
  }
  return ids;
}

/// Every robot has a merged trajectory within these bounds of the truth (a wrong merge is metres off).
void expect_every_robot_placed(const eval::MissionScore& score, double max_rmse_m, double max_error_m) {
  for (const auto& robot : score.robots) {
    ASSERT_TRUE(robot.global) << "robot " << robot.robot.value << " has no merged trajectory";
    EXPECT_GE(robot.keyframes, 10);
    EXPECT_LT(robot.global->ate_rmse_m, max_rmse_m) << "robot " << robot.robot.value;
    EXPECT_LT(robot.global->ate_max_m, max_error_m) << "robot " << robot.robot.value;
  }
}

/// A whole text file (a process's log); empty when it cannot be read.
std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// The office mission (3 robots) ended well with every robot on the map, right.
void expect_office_mission_placed_every_robot(const MissionRun& run) {
  ASSERT_EQ(run.result.exit_code, 0) << run.result.output;
  EXPECT_EQ(run.result.output.find("NOT LINKED"), std::string::npos) << run.result.output;
  const eval::MissionScore score =
      eval::evaluate_mission((run.out / "ground_truth").string(), (run.out / "map").string());
  ASSERT_EQ(score.robots.size(), 3u);
  expect_every_robot_placed(score, 0.3, 0.6);
}

/// Fraction of the merged map's occupied cells that lie within `tolerance_m` of a floor-plan wall.
double wall_agreement(const fs::path& map_dir, const std::string& world_yaml, double tolerance_m) {
  const auto map_cfg = YamlConfig::load((map_dir / "map.yaml").string());
  const double map_res = map_cfg.require<double>("resolution");
  const auto origin = map_cfg.node()["origin"].as<std::vector<double>>();
  const Pgm map = read_pgm((map_dir / "map.pgm").string());

  const auto world = YamlConfig::load(world_yaml);
  const double plan_res = world["map"].require<double>("resolution_m");
  const auto plan_origin = world["map"].node()["origin_m"].as<std::vector<double>>();
  const fs::path image = fs::path(world_yaml).parent_path() / world["map"].require<std::string>("image");
  const Pgm plan = read_pgm(image.string());
  if (map.pixels.empty() || plan.pixels.empty()) return 0.0;

  const int r = int(std::ceil(tolerance_m / plan_res));
  int occupied = 0, near_wall = 0;
  for (int row = 0; row < map.height; ++row) {
    for (int col = 0; col < map.width; ++col) {
      if (map.at(col, row) != 0) continue;
      ++occupied;
      const double x = origin[0] + (col + 0.5) * map_res, y = origin[1] + (row + 0.5) * map_res;
      const int pc = int(std::floor((x - plan_origin[0]) / plan_res));
      const int pr = int(std::floor((y - plan_origin[1]) / plan_res));
      bool hit = false;
      for (int dr = -r; dr <= r && !hit; ++dr) {
        for (int dc = -r; dc <= r && !hit; ++dc) {
          const int c = pc + dc, rr = pr + dr;
          hit = c >= 0 && rr >= 0 && c < plan.width && rr < plan.height && plan.at(c, rr) < 128;
        }
      }
      near_wall += hit;
    }
  }
  return occupied ? double(near_wall) / occupied : 0.0;
}

TEST(MissionIntegration, TwoRobotsOverSecureDdsMatchGroundTruth) {
  // Robot 1's start is not told to the base: it must be linked by verified cross-robot closures.
  // With --secure every process authenticates with its own certificate of a CA made for this
  // mission, and every message is encrypted (a process without one hears nothing: dds/security_test).
  // At 4x real time, not as fast as possible: the base plans on its own clock (every 2 s), and an
  // unpaced 69 s mission can end (5 s of wall time on a loaded machine) before its first plan.
  const std::string world = "tests/worlds/two_robots_meet.yaml";
  const MissionRun run = run_mission(world, "mission", "--timeout 400 --secure --speed 4");
  const fs::path& out = run.out;
  const CommandResult& r = run.result;
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("Mission summary"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("DDS Security on"), std::string::npos) << r.output;
  for (const char* who : {"base", "sim", "robot0", "robot1"}) {
    EXPECT_TRUE(fs::exists(out / "security" / who / "cert.pem")) << who;
  }
  // The base plans where to search next and sends each linked robot its goal (cairn/goal).
  const std::string agent0_log = read_text(out / "logs" / "agent0.log");
  EXPECT_NE(agent0_log.find(" from the base, id "), std::string::npos) << agent0_log;
  std::ifstream summary_in(out / "map" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(summary_in);
  EXPECT_GE(summary["exploration"]["goals"].size(), 1u) << summary["exploration"].dump();

  for (const char* f : {"map.pgm", "map.yaml", "map.png", "objects.geojson", "objects.csv", "objects.bt", "graph.g2o",
                        "summary.json"}) {
    EXPECT_TRUE(fs::exists(out / "map" / f)) << f;
  }
  int ply = 0;
  for (const auto& e : fs::directory_iterator(out / "map")) ply += e.path().extension() == ".ply";
  EXPECT_GE(ply, 1);

  const eval::MissionScore score = eval::evaluate_mission((out / "ground_truth").string(), (out / "map").string());
  ASSERT_EQ(score.robots.size(), 2u);
  // Bounds for a robot placed by the base's own cross-robot closures (measured: robot 0 ~0.05 m,
  // robot 1 ~0.12-0.26 m RMSE, a residual rotation of its half of the map); a wrong merge is
  // metres off (the look-alike wings put robot 1 15 m away).
  expect_every_robot_placed(score, 0.35, 0.60);
  EXPECT_GE(score.objects.ground_truth, 4);
  EXPECT_GE(score.objects.recall(), 0.75) << eval::format_score(score);
  EXPECT_GE(score.objects.precision(), 0.75) << eval::format_score(score);
  EXPECT_LT(score.objects.mean_error_xy_m, 0.35) << eval::format_score(score);

  // The merged map's walls are where the floor plan has them.
  EXPECT_GT(wall_agreement(out / "map", source_path(world), 0.20), 0.90);
}

TEST(MissionIntegration, DemoFloorMergesEveryRobotAndEveryObjectOnceAndSurvivesABaseRestart) {
  // The demo (scripts/demo.sh): 4 robots on the collapsed floor, none of their starts told to the
  // base but robot 0's. Every robot must be linked (robot 1 used to be refused by walls seen from
  // far away), placed without a wrong merge, and each object reported once.
  const std::string world = "worlds/collapsed.yaml";
  const MissionRun run = run_mission(world, "demo", "--timeout 600");
  const fs::path& out = run.out;
  const CommandResult& r = run.result;
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("NOT LINKED"), std::string::npos) << r.output;
  const eval::MissionScore score = eval::evaluate_mission((out / "ground_truth").string(), (out / "map").string());
  ASSERT_EQ(score.robots.size(), 4u);
  // The robots explore by themselves. Measured 0.025-0.31 m RMSE over runs: nearly all of it is the
  // whole map turned up to ~0.9 deg about robot 0's start (the anchor: its first turns in place
  // leave that much heading error in its own SLAM; a known weakness, docs/benchmarks.md); the map
  // in itself is 0.011-0.015 m, checked below. A wrong merge is metres off.
  expect_every_robot_placed(score, 0.50, 0.80);
  // Most of that is the whole map turned ~0.18 deg about robot 0's start (the anchor); in itself,
  // every robot aligned to the truth by one rigid transform, the merged map measured 0.017 m.
  ASSERT_TRUE(score.map_consistency);
  EXPECT_EQ(score.map_consistency->robots, 4);
  EXPECT_LT(score.map_consistency->ate_rmse_m, 0.05) << eval::format_score(score);
  EXPECT_EQ(score.objects.ground_truth, 8);
  EXPECT_GE(score.objects.recall(), 0.85) << eval::format_score(score);
  // Exploring by themselves the robots see objects from more sides than the scripted routes did.
  // An end of a 1.6 m victim box seen alone, or a door placed by the floor homography from beyond
  // the depth range, used to stay a second report (0.67-1.0 over CI runs); they are joined now
  // (batch merges of 12 journals: 0.8-1.0, mean 0.97). Left: a robot's own sighting far off.
  EXPECT_GE(score.objects.precision(), 0.75) << eval::format_score(score);
  EXPECT_GT(wall_agreement(out / "map", source_path(world), 0.20), 0.90);
  // Every robot's time to link is reported (mission seconds; 0 for the anchor), and nothing is left
  // only in a robot's own frame.
  std::ifstream results_in(out / "results.json");
  const nlohmann::json results = nlohmann::json::parse(results_in, nullptr, false);
  ASSERT_FALSE(results.is_discarded());
  ASSERT_EQ(results["robots"].size(), 4u);
  for (const auto& robot : results["robots"]) {
    ASSERT_TRUE(robot["time_to_link_s"].is_number()) << robot.dump();
    EXPECT_GE(robot["time_to_link_s"].get<double>(), 0.0) << robot.dump();
    if (robot["id"] == 0) EXPECT_EQ(robot["time_to_link_s"].get<double>(), 0.0);
  }
  EXPECT_TRUE(results["unlinked_robots"].empty()) << results["unlinked_robots"].dump();
  EXPECT_TRUE(results["unplaced_objects"].empty()) << results["unplaced_objects"].dump();

  // The base station restarted after the mission, with every robot gone: from its journal alone
  // it must rebuild the same merge (all 4 robots linked, every object once, objects included).
  const fs::path again = out / "map_restarted";
  fs::create_directories(again);
  fs::copy_file(out / "map" / "journal.sqlite", again / "journal.sqlite");
  const auto start = YamlConfig::load(source_path(world)).node()["robots"][0]["start"].as<std::vector<double>>();
  std::string error;
  const auto lease = dds::DomainLease::claim({}, &error);  // no other mission's robots on it
  ASSERT_TRUE(lease) << error;
  const CommandResult b =
      run_command("timeout 120 " + bin("cairn_base") + " --domain " + std::to_string(lease->domain_id()) + " --out " +
                  again.string() + " --robots 4 --port 0 --start 0," + std::to_string(start[0]) + "," +
                  std::to_string(start[1]) + "," + std::to_string(start[2]));
  ASSERT_EQ(b.exit_code, 0) << b.output;
  const eval::MissionScore restored = eval::evaluate_mission((out / "ground_truth").string(), again.string());
  ASSERT_EQ(restored.robots.size(), 4u);
  expect_every_robot_placed(restored, 0.50, 0.80);  // as above (solved in one batch)
  ASSERT_TRUE(restored.map_consistency);
  EXPECT_LT(restored.map_consistency->ate_rmse_m, 0.05) << eval::format_score(restored);
  EXPECT_EQ(restored.objects.matched, score.objects.matched) << eval::format_score(restored);
  // A duplicate left by the live merge may be joined in the restarted batch merge (9 against 10 seen).
  EXPECT_NEAR(restored.objects.detected, score.objects.detected, 1) << eval::format_score(restored);
  EXPECT_GE(restored.objects.precision(), 0.75) << eval::format_score(restored);
  // Every object keeps the id the team knew it by (as its id, or an alias of the object it joined).
  const std::set<std::string> known = object_ids_in(out / "map" / "objects.csv");
  const std::set<std::string> after = object_ids_in(again / "objects.csv");
  ASSERT_FALSE(known.empty());
  for (const std::string& id : known) EXPECT_TRUE(after.count(id)) << id << " lost its id when the base restarted";
}

TEST(MissionIntegration, TwoRobotsExploreTheOfficeByThemselvesFindEverythingAndComeHome) {
  // No route anywhere: the base plans, the agents navigate, the simulator obeys their cmd_vel in
  // lock-step. Both robots must cover the floor, find every object and end the mission at home.
  // The attentive strategy (coordinated + the saliency layer); the demo test runs the default.
  const std::string world = "tests/worlds/two_robots_explore.yaml";
  const MissionRun run = run_mission(world, "explore", "--timeout 600 --exploration saliency");
  const fs::path& out = run.out;
  const CommandResult& r = run.result;
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const eval::MissionScore score = eval::evaluate_mission((out / "ground_truth").string(), (out / "map").string());
  ASSERT_EQ(score.robots.size(), 2u);
  expect_every_robot_placed(score, 0.20, 0.35);
  ASSERT_TRUE(score.coverage);
  EXPECT_GE(score.coverage->fraction(), 0.95) << eval::format_score(score);
  EXPECT_EQ(score.objects.ground_truth, 7);
  EXPECT_DOUBLE_EQ(score.objects.recall(), 1.0) << eval::format_score(score);
  EXPECT_GE(score.objects.precision(), 0.87) << eval::format_score(score);  // at most one duplicate (see the demo)
  // Home: the mission ended before the world's 400 s limit because both robots said so, each
  // back where it entered.
  std::ifstream results_in(out / "results.json");
  const nlohmann::json results = nlohmann::json::parse(results_in, nullptr, false);
  ASSERT_FALSE(results.is_discarded());
  EXPECT_LT(results["simulated_s"].get<double>(), 399.0) << r.output;
  // The base sent them home once (a frontier seen on the way home may call them out again).
  EXPECT_TRUE(results["exploration"]["sent_home"].get<bool>()) << results["exploration"].dump();
  ASSERT_TRUE(results["exploration"]["sent_home_at_s"].is_number());
  EXPECT_LT(results["exploration"]["sent_home_at_s"].get<double>(), results["simulated_s"].get<double>());
  for (int id : {0, 1}) {
    const Trajectory truth =
        read_trajectory_csv((out / "ground_truth" / ("gt_robot" + std::to_string(id) + ".csv")).string());
    ASSERT_FALSE(truth.empty());
    // Home is within 1 m of where it entered by its own estimate (MissionBehaviourOptions::
    // home_tolerance_m), or within 3 m when the other robot, parked at its own entry 1.3 m away,
    // blocks the last metres (home_area_m); the estimate is a few centimetres off the truth.
    EXPECT_LT((truth.back().pose.translation() - truth.front().pose.translation()).norm(), 3.2) << "robot " << id;
  }
  EXPECT_NE(r.output.find("exploration: 50 % covered at"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(out / "coverage.png"));
  // The cameras' salient spots reached the base for its saliency layer (the victims and hazards are
  // the only colourful things in the simulated office).
  std::ifstream summary_in(out / "map" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(summary_in, nullptr, false);
  ASSERT_FALSE(summary.is_discarded());
  EXPECT_GT(summary["exploration"]["salient_spots_received"].get<int>(), 0);
}

TEST(MissionIntegration, ARobotWhoseLaserBreaksGoesHomeByOdometryAndItsDataReachesTheMap) {
  // Robot 1's laser dies 40 s into the exploration. It must not be dropped: keyframes from odometry
  // alone reach the base (its merged trajectory goes on past 40 s, near the truth), it drives home
  // blind by the map it has, and the mission ends because both robots said they are done.
  const std::string world = "tests/worlds/laser_breaks.yaml";
  // A tight entry hint (the demo's 0.5 m / 10 deg) stands in for the 2 m spread of the closures:
  // robot 1's 40 s of scans stay within a metre or so of its start, and with a loose one (1 m /
  // 20 deg) it waits for a spread that may never come (one of two runs: never linked). Once in CI
  // it ended 6 m / 21 deg off although the five closures that linked it were right: its odometry-
  // only keyframes of turns in place came with information 4e17 and the pose graph could not
  // converge after the link (now floored on both sides: ChainEdge.*, Keyframer.*).
  const MissionRun run = run_mission(world, "laser_breaks", "--timeout 600 --entry-hints 0.5,10");
  const fs::path& out = run.out;
  const CommandResult& r = run.result;
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string agent1 = read_text(out / "logs" / "agent1.log");
  EXPECT_NE(agent1.find("laser silent"), std::string::npos) << agent1.substr(0, 2000);
  std::ifstream summary_in(out / "map" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(summary_in, nullptr, false);
  ASSERT_FALSE(summary.is_discarded());
  ASSERT_EQ(summary["robots"].size(), 2u);
  for (const auto& robot : summary["robots"]) {
    EXPECT_EQ(robot["keyframes"], robot["link"]["keyframes_sent"]) << robot.dump();
    EXPECT_TRUE(robot["link"]["finished"].get<bool>()) << robot.dump();
  }
  const Trajectory merged = read_trajectory_csv((out / "map" / "trajectory_robot1.csv").string());
  const Trajectory truth = read_trajectory_csv((out / "ground_truth" / "gt_robot1.csv").string());
  ASSERT_FALSE(merged.empty());
  ASSERT_FALSE(truth.empty());
  EXPECT_GT(ns_to_sec(merged.back().stamp_ns), 45.0) << "keyframes made after the laser died reached the map";
  // Dead reckoning drifts with the odometry (5 cm per metre), so a metre is allowed here.
  const auto truth_at_end = interpolate_pose(truth, merged.back().stamp_ns, kNsPerSec);
  ASSERT_TRUE(truth_at_end);
  EXPECT_LT((merged.back().pose.translation() - truth_at_end->translation()).norm(), 1.0);
  // Home: back where it entered, give or take the home area and the drift.
  EXPECT_LT((truth.back().pose.translation() - truth.front().pose.translation()).norm(), 3.5);
}

TEST(MissionIntegration, RobotsThatNeverMeetInLookAlikeWingsAreNotMergedWrongly) {
  // The office's west and east wings look alike and the robots never see the same place: robot 1
  // must not be linked on scans (a late merge is fine, a wrong one is not). They do see each other
  // down the corridor at the end, and a link on those sightings must put robot 1 right.
  const MissionRun run = run_mission("tests/worlds/two_robots.yaml", "aliasing", "--timeout 400");
  const fs::path& out = run.out;
  const CommandResult& r = run.result;
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const eval::MissionScore score = eval::evaluate_mission((out / "ground_truth").string(), (out / "map").string());
  ASSERT_EQ(score.robots.size(), 2u);
  ASSERT_TRUE(score.robots[0].global);
  EXPECT_LT(score.robots[0].global->ate_rmse_m, 0.20);
  if (score.robots[1].global) {
    EXPECT_LT(score.robots[1].global->ate_max_m, 0.5) << "robot 1 was merged in the wrong place";
    const std::string log = read_text(out / "logs" / "base.log");
    EXPECT_TRUE(std::regex_search(log, std::regex("linked via [0-9]+ shared sightings"))) << "linked, not on sightings";
  } else {
    EXPECT_NE(r.output.find("robot 1 (NOT LINKED to the map)"), std::string::npos) << r.output;
  }
}

TEST(MissionIntegration, TheOfficesThreeRobotsAllJoinTheMapAndTheirSightingsOfEachOtherHoldItTogether) {
  // Robots 1 and 2 enter far from robot 0 and overlap its rooms mostly in look-alike corridor pieces.
  // Each is linked by whichever verified evidence comes first: the markers the robots' cameras see on
  // each other, or (in about half the runs, for one of them) a scan closure through a room they share.
  // Either way every robot must end up placed right, and the sightings must reach the global graph:
  // a link made on them, or sighting nodes among the linked robots' poses.
  const MissionRun run = run_mission("worlds/office.yaml", "office", "--timeout 600");
  ASSERT_NO_FATAL_FAILURE(expect_office_mission_placed_every_robot(run));
  const std::string log = read_text(run.out / "logs" / "base.log");
  const bool linked_on_sightings = std::regex_search(log, std::regex("linked via [0-9]+ shared sightings"));
  const std::string graph = read_text(run.out / "map" / "graph.g2o");
  const bool sightings_in_graph = std::regex_search(graph, std::regex("\\n# SIGHTING [0-9]+ [0-9]+"));
  EXPECT_TRUE(linked_on_sightings || sightings_in_graph) << "no sighting linked a robot nor reached the graph";
}

TEST(MissionIntegration, OfficeRobotsNotOnTheMapAreSentToMeetATeammateAndLinkedRight) {
  // Active linking: with entry hints the base sends robots 1 and 2 (not placed after a few seconds)
  // toward robot 0 where their hints put them; what they then see of each other links them, through
  // the same checks as ever (a hint is never a link).
  const MissionRun run = run_mission("worlds/office.yaml", "meet", "--timeout 600 --entry-hints 0.5,10");
  ASSERT_NO_FATAL_FAILURE(expect_office_mission_placed_every_robot(run));
  const std::string log = read_text(run.out / "logs" / "base.log");
  EXPECT_TRUE(std::regex_search(log, std::regex("robot[12] not on the map [0-9]+ s after its first keyframe: sent to "
                                                "meet robot[0-9]")))
      << log.substr(0, 3000);
  EXPECT_TRUE(std::regex_search(log, std::regex("robot[12] linked while meeting"))) << "no meeting ended in a link";
  std::ifstream summary_in(run.out / "map" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(summary_in, nullptr, false);
  ASSERT_FALSE(summary.is_discarded());
  EXPECT_GE(summary["exploration"]["meetings"]["linked"].get<int>(), 1) << summary["exploration"].dump();
}

}  // namespace
}  // namespace cairn::test
