#include "sim/world.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "common/errors.h"
#include "sim/reachable_area.h"
#include "sim/rgbd_renderer.h"
#include "sim/simulator.h"

namespace cairn::sim {
namespace {

const std::string kWorlds = std::string(CAIRN_SOURCE_DIR) + "/worlds/";

// Every segment between consecutive waypoints (from the start), inflated by the robot radius.
void expect_routes_free(const World& world) {
  for (const RobotSpec& r : world.robots) {
    Eigen::Vector2d from = r.T_world_start.translation();
    for (const Eigen::Vector2d& to : r.waypoints_m) {
      EXPECT_TRUE(world.floor_plan.segment_free(from, to, 0.2))
          << to_string(r.id) << ": segment (" << from.transpose() << ") -> (" << to.transpose() << ")";
      from = to;
    }
  }
}

struct MissionSummary {
  double end_s = 0;
  std::map<int, int> best_pixels;  ///< object id -> most pixels seen within 4 m in one frame
};

// Runs the mission without sensors, then renders every 0.5 s of ground truth with object labels.
MissionSummary run_mission(const WorldFile& file) {
  SimOptions options = file.sim;
  options.enable_camera = false;
  options.enable_laser = false;
  Simulator sim(file.world, options);
  while (!sim.done()) sim.step();
  MissionSummary out;
  out.end_s = ns_to_sec(sim.now_ns());
  for (RobotId id : sim.robot_ids()) {
    EXPECT_TRUE(sim.robot_finished(id)) << to_string(id);
    EXPECT_EQ(sim.collisions(id), 0) << to_string(id) << ": the scripted route touches a wall or a robot";
  }
  const RgbdRenderer renderer(file.sim.camera, file.world.floor_plan, file.world.wall_height_m, file.world.objects);
  std::mt19937_64 rng(1);
  for (RobotId id : sim.robot_ids()) {
    const Trajectory& gt = sim.ground_truth(id);
    for (size_t i = 0; i < gt.size(); i += 10) {
      std::vector<int> ids;
      const RgbdFrame f = renderer.render(gt[i].pose, gt[i].stamp_ns, rng, &ids);
      std::map<int, int> count;
      for (size_t p = 0; p < ids.size(); ++p) {
        if (ids[p] >= 0 && f.depth[p] > 0 && f.depth[p] < 4000) ++count[ids[p]];
      }
      for (const auto& [obj, n] : count) out.best_pixels[obj] = std::max(out.best_pixels[obj], n);
    }
  }
  return out;
}

void check_shipped_world(const std::string& name, double min_s, double max_s) {
  // Without its routes file a shipped world loads with robots that wait for velocity commands.
  const WorldFile commanded = load_world_file(kWorlds + name + ".yaml");
  EXPECT_EQ(commanded.sim.drive_mode, DriveMode::kCommands);
  for (const RobotSpec& r : commanded.world.robots) EXPECT_TRUE(r.waypoints_m.empty()) << to_string(r.id);
  WorldLoadOptions options;
  options.routes_path = kWorlds + "routes/" + name + ".yaml";
  const WorldFile file = load_world_file(kWorlds + name + ".yaml", options);
  EXPECT_EQ(file.sim.drive_mode, DriveMode::kWaypoints);
  const World& world = file.world;
  for (const RobotSpec& r : world.robots) EXPECT_GE(r.waypoints_m.size(), 5u) << to_string(r.id);
  EXPECT_EQ(world.name, name);
  EXPECT_GE(world.robots.size(), 3u);
  EXPECT_GE(world.objects.size(), 6u);
  std::map<std::string, int> classes;
  for (const WorldObject& o : world.objects) ++classes[o.object_class];
  EXPECT_EQ(classes.size(), 3u);
  expect_routes_free(world);
  const MissionSummary m = run_mission(file);
  EXPECT_GE(m.end_s, min_s);
  EXPECT_LE(m.end_s, max_s);
  for (const WorldObject& o : world.objects) {
    const auto it = m.best_pixels.find(o.id);
    EXPECT_TRUE(it != m.best_pixels.end() && it->second >= 50)
        << name << ": object " << o.id << " (" << o.object_class << ") not seen within 4 m";
  }
}

TEST(ShippedWorlds, Office) { check_shipped_world("office", 60.0, 90.0); }
TEST(ShippedWorlds, Collapsed) { check_shipped_world("collapsed", 120.0, 180.0); }

// The large generated world: no routes at all; big enough, a team of 6+, 12+ objects of every class,
// and every object next to space a robot can drive to (sim/reachable_area.h).
TEST(ShippedWorlds, RubbleSiteIsLargeAndEveryObjectCanBeReached) {
  const WorldFile file = load_world_file(kWorlds + "rubble_site.yaml");
  EXPECT_EQ(file.sim.drive_mode, DriveMode::kCommands);
  const World& world = file.world;
  const Eigen::Vector2d size_m = world.floor_plan.max_m() - world.floor_plan.origin_m();
  EXPECT_GE(size_m.x(), 60.0);
  EXPECT_GE(size_m.y(), 40.0);
  EXPECT_GE(world.robots.size(), 6u);
  EXPECT_GE(world.objects.size(), 12u);
  std::map<std::string, int> classes;
  for (const WorldObject& o : world.objects) ++classes[o.object_class];
  EXPECT_EQ(classes.size(), 3u);
  std::vector<Eigen::Vector2d> starts;
  for (const RobotSpec& r : world.robots) {
    EXPECT_TRUE(r.waypoints_m.empty());
    starts.push_back(r.T_world_start.translation());
  }
  const FloorPlan& plan = world.floor_plan;
  const std::vector<uint8_t> explorable = reachable_free_cells(plan, starts);
  int explorable_cells = 0;
  for (uint8_t v : explorable) explorable_cells += v;
  EXPECT_GT(explorable_cells * plan.resolution_m() * plan.resolution_m(), 1500.0);
  for (const WorldObject& o : world.objects) {
    bool near = false;
    const Eigen::Vector2i c = plan.cell_of(o.center_m.head<2>());
    for (int dr = -30; dr <= 30 && !near; ++dr) {
      for (int dc = -30; dc <= 30 && !near; ++dc) {
        near = plan.contains(c.x() + dc, c.y() + dr) && explorable[size_t(c.y() + dr) * plan.width() + c.x() + dc];
      }
    }
    EXPECT_TRUE(near) << "object " << o.id << " (" << o.object_class << ") is out of every robot's reach";
  }
}

// Writes a world YAML (and a 4 m x 4 m image with a wall block) into a temp dir.
class BadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    // One folder per process: ctest -j runs the BadInput tests side by side.
    dir_ = std::filesystem::temp_directory_path() / ("cairn_sim_world_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
    std::ofstream img(dir_ / "plan.pgm", std::ios::binary);
    img << "P5\n80 80\n255\n";
    for (int r = 0; r < 80; ++r)
      for (int c = 0; c < 80; ++c) img.put(char(c >= 40 && c < 50 && r >= 30 && r < 50 ? 0 : 254));
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string write(const std::string& text, const std::string& name = "w.yaml") {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  static std::string yaml(const std::string& map, const std::string& robot, const std::string& objects = "") {
    return "map: {" + map + "}\nrobots:\n  - {" + robot + "}\n" + objects;
  }
  // Expects InputError whose message names the file and contains `key`.
  void expect_error(const std::string& text, const std::string& key) {
    const std::string path = write(text);
    try {
      load_world_file(path);
      ADD_FAILURE() << "no error for key " << key;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(path), std::string::npos) << msg;
      EXPECT_NE(msg.find(key), std::string::npos) << msg;
    }
  }
  std::filesystem::path dir_;
  const std::string good_map_ = "image: plan.pgm, resolution_m: 0.05";
  const std::string good_robot_ = "id: 0, start: [1, 1, 0], waypoints: [[3, 1]]";
};

TEST_F(BadInput, GoodFileLoads) {
  const WorldFile f = load_world_file(write(yaml(good_map_, good_robot_)));
  EXPECT_EQ(f.world.floor_plan.width(), 80);
  EXPECT_TRUE(f.world.floor_plan.wall_at(Eigen::Vector2d(2.2, 2.0)));  // image row 30..49 from the top
  EXPECT_FALSE(f.world.floor_plan.wall_at(Eigen::Vector2d(2.2, 0.5)));
}

TEST_F(BadInput, MissingFile) {
  EXPECT_THROW(load_world_file((dir_ / "nope.yaml").string()), InputError);
  expect_error(yaml("image: nope.pgm, resolution_m: 0.05", good_robot_), "map.image");
}

TEST_F(BadInput, MalformedYaml) {
  const std::string path = write("map: {image: plan.pgm, resolution_m: [0.05\nrobots: - x");
  try {
    load_world_file(path);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
  }
}

TEST_F(BadInput, MissingKey) {
  expect_error(yaml("image: plan.pgm", "id: 0, waypoints: []"), "robots[0].start");
  expect_error("robots: []\n", "map");
}

TEST_F(BadInput, InvalidValues) {
  expect_error(yaml("image: plan.pgm, resolution_m: -0.05", good_robot_), "map.resolution_m");
  expect_error(yaml(good_map_, "id: 0, start: [2.2, 2.0, 0]"), "robots[0].start");  // inside the wall
  expect_error(yaml(good_map_, "id: 0, start: [1, .nan, 0]"), "robots[0].start");
  expect_error(yaml(good_map_, "id: 0, start: [1, 1]"), "robots[0].start");
  expect_error(yaml(good_map_, good_robot_,
                    "objects:\n  - {id: 0, class: cat, color: [1, 2, 3], size_m: [1, 1, 1], pose: [1, 1, 0, 0]}\n"),
               "objects[0].class");
  expect_error(
      yaml(
          good_map_, good_robot_,
          "objects:\n  - {id: 0, class: exit, shape: cone, color: [1, 2, 3], size_m: [1, 1, 1], pose: [1, 1, 0, 0]}\n"),
      "objects[0].shape");
  expect_error(yaml(good_map_, good_robot_,
                    "objects:\n  - {id: 0, class: exit, color: [1, 2, 3], size_m: [1, 1, 1], pose: [1, .nan, 0, 0]}\n"),
               "objects[0].pose");
  expect_error(yaml(good_map_, good_robot_) + "sensors: {laser: {beams: -3}}\n", "sensors.laser.beams");
}

TEST_F(BadInput, DriveModeIsWaypointsOnlyWhenARobotHasWaypointsOrTheSimSectionSaysSo) {
  const std::string still = "id: 0, start: [1, 1, 0]";
  WorldFile f = load_world_file(write(yaml(good_map_, still)));  // no waypoints: loads, commands
  EXPECT_EQ(f.sim.drive_mode, DriveMode::kCommands);
  EXPECT_TRUE(f.world.robots.at(0).waypoints_m.empty());
  f = load_world_file(write(yaml(good_map_, good_robot_)));
  EXPECT_EQ(f.sim.drive_mode, DriveMode::kWaypoints);
  EXPECT_EQ(f.world.robots.at(0).waypoints_m.size(), 1u);
  f = load_world_file(write(yaml(good_map_, good_robot_) + "sim: {drive: commands}\n"));
  EXPECT_EQ(f.sim.drive_mode, DriveMode::kCommands);
  f = load_world_file(write(yaml(good_map_, still) + "sim: {drive: waypoints, robot_radius_m: 0.3}\n"));
  EXPECT_EQ(f.sim.drive_mode, DriveMode::kWaypoints);
  EXPECT_EQ(f.sim.robot_radius_m, 0.3);
  EXPECT_EQ(load_world_file(write(yaml(good_map_, still))).sim.robot_radius_m, 0.2);
  expect_error(yaml(good_map_, still) + "sim: {drive: fly}\n", "sim.drive");
  expect_error(yaml(good_map_, still) + "sim: {robot_radius_m: 0}\n", "sim.robot_radius_m");
  // The sim's robot radius also keeps the starts off the walls (the wall block is 1.1 m away) and
  // apart from each other.
  expect_error(yaml(good_map_, still) + "sim: {robot_radius_m: 1.2}\n", "robots[0].start");
  expect_error(yaml(good_map_, still) + "  - {id: 1, start: [1.3, 1, 0]}\n", "robots[1].start");
}

TEST_F(BadInput, RoutesFileFillsTheWaypointsAndSetsWaypointMode) {
  const std::string world = write(yaml(good_map_, "id: 0, start: [1, 1, 0], waypoints: [[1, 3]]") +
                                  "  - {id: 4, start: [1, 3, 0]}\nsim: {drive: commands}\n");
  WorldLoadOptions options;
  options.routes_path = write("routes:\n  - {robot: 4, waypoints: [[3, 3], [3.5, 0.5]]}\n", "routes.yaml");
  const WorldFile f = load_world_file(world, options);
  EXPECT_EQ(f.sim.drive_mode, DriveMode::kWaypoints);
  EXPECT_TRUE(f.world.robots.at(0).waypoints_m.empty());  // not listed: no route (the world's is replaced)
  ASSERT_EQ(f.world.robots.at(1).waypoints_m.size(), 2u);
  EXPECT_EQ(f.world.robots.at(1).waypoints_m[1], Eigen::Vector2d(3.5, 0.5));
}

TEST_F(BadInput, RoutesFileErrorsNameTheFileAndKey) {
  const std::string world = write(yaml(good_map_, "id: 0, start: [1, 1, 0]"));
  const auto expect_routes_error = [&](const std::string& text, const std::string& key) {
    WorldLoadOptions options;
    options.routes_path = write(text, "routes.yaml");
    try {
      load_world_file(world, options);
      ADD_FAILURE() << "no error for " << text;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(options.routes_path), std::string::npos) << msg;
      EXPECT_NE(msg.find(key), std::string::npos) << msg;
    }
  };
  expect_routes_error("routes:\n  - {robot: 7, waypoints: [[3, 1]]}\n", "routes[0].robot");
  expect_routes_error("routes:\n  - {robot: 0, waypoints: [[3, x]]}\n", "routes[0].waypoints[0]");
  expect_routes_error("routes:\n  - {robot: 0, waypoints: [[3, 1, 2]]}\n", "routes[0].waypoints[0]");
  expect_routes_error("routes:\n  - {robot: 0, waypoints: [[3, .nan]]}\n", "routes[0].waypoints[0]");
  expect_routes_error("routes:\n  - {robot: 0, waypoints: [[2.2, 2.0]]}\n", "routes[0].waypoints[0]");  // wall
  expect_routes_error("routes:\n  - {robot: zero, waypoints: []}\n", "routes[0].robot");
  expect_routes_error("routes:\n  - {robot: 0, wayponts: [[3, 1]]}\n", "routes[0].wayponts");
  expect_routes_error("routes:\n  - {robot: 0, waypoints: []}\n  - {robot: 0, waypoints: []}\n", "routes[1].robot");
  expect_routes_error("route: []\n", "route");
  expect_routes_error("routes: [\n", "line");
  WorldLoadOptions missing;
  missing.routes_path = (dir_ / "no_routes.yaml").string();
  EXPECT_THROW(load_world_file(world, missing), InputError);
}

TEST_F(BadInput, TheRadioSectionIsCheckedAndItsAntennasDefaultToTheRobotsStarts) {
  const WorldFile plain = load_world_file(write(yaml(good_map_, good_robot_)));
  ASSERT_EQ(plain.world.radio.antennas_m.size(), 1u);
  EXPECT_TRUE(plain.world.radio.antennas_m[0].isApprox(Eigen::Vector2d(1, 1)));
  const WorldFile set = load_world_file(
      write(yaml(good_map_, good_robot_) + "radio: {antennas_m: [[0.5, 3.5], [3.5, 0.5]], wall_loss_db: 7}\n"));
  ASSERT_EQ(set.world.radio.antennas_m.size(), 2u);
  EXPECT_DOUBLE_EQ(set.world.radio.wall_loss_db, 7.0);
  expect_error(yaml(good_map_, good_robot_) + "radio: {antennas_m: [[2.2, 2.0]]}\n", "radio.antennas_m[0]");  // wall
  expect_error(yaml(good_map_, good_robot_) + "radio: {sensitivity_dbm: 10}\n", "radio.sensitivity_dbm");
  expect_error(yaml(good_map_, good_robot_) + "radio: {period_s: .nan}\n", "radio.period_s");
  expect_error(yaml(good_map_, good_robot_) + "radio: {path_loss_exponent: 1e300}\n", "radio.path_loss_exponent");
  expect_error(yaml(good_map_, good_robot_) + "radio: {antenna: [1, 1]}\n", "antenna");
}

// Found by fuzzing world files: each aborted or hung every binary that reads worlds.
TEST_F(BadInput, FuzzedWorldsAreNamedNotCrashedOrRun) {
  expect_error("name: x\n[k]: 1\n", "not a plain name");  // threw an uncaught yaml-cpp exception
  expect_error(yaml(good_map_, good_robot_) + "{a: 1}: 2\n", "not a plain name");
  expect_error(yaml(good_map_, good_robot_) + "sim: {dt_s: 1e300}\n", "sim.dt_s");  // looped for ever
  expect_error(yaml(good_map_, "id: 0, start: [1, 1, 0], max_speed_mps: 1e300"), "robots[0].max_speed_mps");
  expect_error(yaml(good_map_, "id: 0, start: [1, 1, 0], max_turn_radps: 1e308"), "robots[0].max_turn_radps");
  expect_error(yaml(good_map_, good_robot_) + "sim: {duration_s: 1e20}\n", "sim.duration_s");
  expect_error(yaml(good_map_, "id: 0, start: [1, 1, 0], laser_fails_at_s: -3"), "robots[0].laser_fails_at_s");
  expect_error(yaml(good_map_, "id: 0, start: [1, 1, 0], laser_fails_at_s: .nan"), "robots[0].laser_fails_at_s");
  expect_error(yaml(good_map_, good_robot_) + "sensors: {laser: {max_range_m: 1e9}}\n", "sensors.laser.max_range_m");
  expect_error(yaml(good_map_, good_robot_) + "sensors: {camera: {width: 1000000}}\n", "sensors.camera.width");
}

TEST(EntryHintSigmas, BothPositiveOrNothing) {
  const auto s = parse_entry_hint_sigmas("0.5,10");
  ASSERT_TRUE(s);
  EXPECT_DOUBLE_EQ(s->xy_m, 0.5);
  EXPECT_DOUBLE_EQ(s->yaw_deg, 10.0);
  for (const char* bad : {"", "0.5", "0.5;10", "0,10", "0.5,-1", "nan,10", "0.5,10,3", "0.5,10x"})
    EXPECT_FALSE(parse_entry_hint_sigmas(bad)) << bad;
}

}  // namespace
}  // namespace cairn::sim
