#include "sim/world.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>

#include "common/errors.h"
#include "common/yaml_config.h"

namespace cairn::sim {
namespace {

// A list of exactly n finite numbers under `key`.
std::vector<double> require_numbers(const YamlConfig& cfg, const std::string& key, size_t n) {
  const auto v = cfg.require<std::vector<double>>(key);
  if (v.size() != n) cfg.fail(key, "must be a list of " + std::to_string(n) + " numbers");
  for (double x : v) {
    if (!std::isfinite(x)) cfg.fail(key, "must contain finite numbers (found NaN or inf)");
  }
  return v;
}

std::string shortest(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", v);
  return text;
}

/// A value in (0, max]: every loaded number is bounded, so a typo like 1e300 is named, not run (a huge
/// dt_s or speed made the simulator loop for ever).
double positive(const YamlConfig& cfg, const std::string& key, double default_value, double max) {
  const double v = cfg.get<double>(key, default_value);
  if (!(v > 0.0) || !(v <= max)) cfg.fail(key, "must be in (0, " + shortest(max) + "] (got " + shortest(v) + ")");
  return v;
}

/// A value in [0, max].
double non_negative(const YamlConfig& cfg, const std::string& key, double default_value, double max) {
  const double v = cfg.get<double>(key, default_value);
  if (!(v >= 0.0) || !(v <= max)) cfg.fail(key, "must be in [0, " + shortest(max) + "] (got " + shortest(v) + ")");
  return v;
}

/// A value in [min, max].
double in_range(const YamlConfig& cfg, const std::string& key, double default_value, double min, double max) {
  const double v = cfg.get<double>(key, default_value);
  if (!(v >= min) || !(v <= max))
    cfg.fail(key, "must be in [" + shortest(min) + ", " + shortest(max) + "] (got " + shortest(v) + ")");
  return v;
}

int positive_int(const YamlConfig& cfg, const std::string& key, int default_value, int max) {
  const int v = cfg.get<int>(key, default_value);
  if (v <= 0 || v > max)
    cfg.fail(key, "must be an integer in [1, " + std::to_string(max) + "] (got " + std::to_string(v) + ")");
  return v;
}

void load_sensors(const YamlConfig& root, SimOptions& sim) {
  if (!root.has("sensors")) return;
  const YamlConfig s = root["sensors"];
  s.allow_only({"odometry", "laser", "camera"});
  if (s.has("odometry")) {
    const YamlConfig o = s["odometry"];
    o.allow_only({"rate_hz", "trans_noise_per_m", "rot_noise_rad_per_m", "rot_noise_per_rad"});
    OdometryOptions& od = sim.odometry;
    od.rate_hz = positive(o, "rate_hz", od.rate_hz, 1000);
    od.trans_noise_per_m = non_negative(o, "trans_noise_per_m", od.trans_noise_per_m, 1);
    od.rot_noise_rad_per_m = non_negative(o, "rot_noise_rad_per_m", od.rot_noise_rad_per_m, 1);
    od.rot_noise_per_rad = non_negative(o, "rot_noise_per_rad", od.rot_noise_per_rad, 1);
  }
  if (s.has("laser")) {
    const YamlConfig l = s["laser"];
    l.allow_only({"rate_hz", "beams", "fov_deg", "max_range_m", "min_range_m", "noise_sd_m"});
    LaserOptions& lo = sim.laser;
    lo.rate_hz = positive(l, "rate_hz", lo.rate_hz, 1000);
    lo.beams = positive_int(l, "beams", lo.beams, 100000);
    lo.fov_deg = positive(l, "fov_deg", lo.fov_deg, 360);
    if (lo.fov_deg > 360.0) l.fail("fov_deg", "must be <= 360");
    lo.max_range_m = positive(l, "max_range_m", lo.max_range_m, 100);
    lo.min_range_m = non_negative(l, "min_range_m", lo.min_range_m, 10);
    lo.noise_sd_m = non_negative(l, "noise_sd_m", lo.noise_sd_m, 1);
  }
  if (s.has("camera")) {
    const YamlConfig c = s["camera"];
    c.allow_only({"rate_hz", "width", "height", "hfov_deg", "max_depth_m", "height_m", "pitch_deg", "forward_offset_m",
                  "depth_noise_sd_m", "rgb_noise_sd", "render_range_m"});
    CameraOptions& co = sim.camera;
    co.rate_hz = positive(c, "rate_hz", co.rate_hz, 100);
    co.width = positive_int(c, "width", co.width, 4096);
    co.height = positive_int(c, "height", co.height, 4096);
    co.hfov_deg = positive(c, "hfov_deg", co.hfov_deg, 170);
    if (co.hfov_deg >= 170.0) c.fail("hfov_deg", "must be < 170");
    co.max_depth_m = positive(c, "max_depth_m", co.max_depth_m, 50);
    if (co.max_depth_m > 65.0) c.fail("max_depth_m", "must be <= 65 (uint16 millimetres)");
    co.height_m = positive(c, "height_m", co.height_m, 5);
    co.pitch_deg = c.get<double>("pitch_deg", co.pitch_deg);
    if (std::abs(co.pitch_deg) >= 80.0) c.fail("pitch_deg", "must be within (-80, 80)");
    co.forward_offset_m = c.get<double>("forward_offset_m", co.forward_offset_m);
    co.depth_noise_sd_m = non_negative(c, "depth_noise_sd_m", co.depth_noise_sd_m, 1);
    co.rgb_noise_sd = non_negative(c, "rgb_noise_sd", co.rgb_noise_sd, 255);
    co.render_range_m = positive(c, "render_range_m", co.render_range_m, 100);
  }
}

DriveMode parse_drive(const YamlConfig& s) {
  const std::string d = s.require<std::string>("drive");
  if (d == "commands") return DriveMode::kCommands;
  if (d == "waypoints") return DriveMode::kWaypoints;
  s.fail("drive", "must be one of commands, waypoints (got '" + d + "')");
}

/// Returns whether the drive mode was given.
bool load_sim(const YamlConfig& root, SimOptions& sim) {
  bool drive_given = false;
  if (root.has("sim")) {
    const YamlConfig s = root["sim"];
    s.allow_only({"seed", "dt_s", "duration_s", "settle_time_s", "drive", "robot_radius_m", "lasers_see_robots",
                  "cameras_see_robots"});
    const long long seed = s.get<long long>("seed", (long long)sim.seed);
    if (seed < 0) s.fail("seed", "must be >= 0");
    sim.seed = uint64_t(seed);
    sim.dt_s = positive(s, "dt_s", sim.dt_s, 1);
    sim.duration_s = positive(s, "duration_s", sim.duration_s, 86400);
    sim.settle_time_s = non_negative(s, "settle_time_s", sim.settle_time_s, 3600);
    sim.robot_radius_m = positive(s, "robot_radius_m", sim.robot_radius_m, 5);
    sim.lasers_see_robots = s.get("lasers_see_robots", sim.lasers_see_robots);
    sim.cameras_see_robots = s.get("cameras_see_robots", sim.cameras_see_robots);
    if (s.has("drive")) sim.drive_mode = parse_drive(s), drive_given = true;
  }
  load_sensors(root, sim);
  return drive_given;
}

/// The waypoints under `key`: each [x, y], finite, on the map and not inside a wall.
std::vector<Eigen::Vector2d> load_waypoints(const YamlConfig& cfg, const std::string& key, const FloorPlan& plan) {
  std::vector<Eigen::Vector2d> out;
  for (const YamlConfig& w : cfg.sequence(key)) {
    const auto v = w.as<std::vector<double>>();
    if (v.size() != 2 || !std::isfinite(v[0]) || !std::isfinite(v[1])) {
      w.fail("", "must be [x, y] with finite numbers");
    }
    const Eigen::Vector2d p(v[0], v[1]);
    if (plan.wall_at(p) || !plan.disc_free(p, 0.0)) w.fail("", "is off the map or inside a wall");
    out.push_back(p);
  }
  return out;
}

/// The `radio:` section (sim/radio_model.h); antennas default to the robots' starts.
RadioOptions load_radio(const YamlConfig& root, const World& world) {
  RadioOptions r;
  if (root.has("radio")) {
    const YamlConfig c = root["radio"];
    c.allow_only({"antennas_m", "tx_power_dbm", "loss_at_1m_db", "path_loss_exponent", "wall_loss_db",
                  "sensitivity_dbm", "hysteresis_db", "reconnect_s", "period_s"});
    if (c.has("antennas_m")) r.antennas_m = load_waypoints(c, "antennas_m", world.floor_plan);
    r.tx_power_dbm = in_range(c, "tx_power_dbm", r.tx_power_dbm, -30, 40);
    r.loss_at_1m_db = in_range(c, "loss_at_1m_db", r.loss_at_1m_db, 0, 100);
    r.path_loss_exponent = in_range(c, "path_loss_exponent", r.path_loss_exponent, 1, 6);
    r.wall_loss_db = in_range(c, "wall_loss_db", r.wall_loss_db, 0, 60);
    r.sensitivity_dbm = in_range(c, "sensitivity_dbm", r.sensitivity_dbm, -130, 0);
    r.hysteresis_db = in_range(c, "hysteresis_db", r.hysteresis_db, 0, 30);
    r.reconnect_s = in_range(c, "reconnect_s", r.reconnect_s, 0, 600);
    r.period_s = in_range(c, "period_s", r.period_s, 0.05, 60);
  }
  if (r.antennas_m.empty()) {
    for (const RobotSpec& robot : world.robots) r.antennas_m.push_back(robot.T_world_start.translation());
  }
  return r;
}

RobotSpec load_robot(const YamlConfig& r, const FloorPlan& plan, double radius_m) {
  RobotSpec spec;
  r.allow_only({"id", "start", "max_speed_mps", "max_turn_radps", "waypoints", "laser_fails_at_s"});
  const int id = r.require<int>("id");
  if (id < 0) r.fail("id", "must be >= 0");
  spec.id = RobotId(id);
  const auto start = require_numbers(r, "start", 3);
  spec.T_world_start = SE2(start[0], start[1], start[2]);
  if (!plan.disc_free(spec.T_world_start.translation(), radius_m)) {
    r.fail("start", "is off the map, inside a wall or closer than " + shortest(radius_m) + " m to one");
  }
  spec.max_speed_mps = positive(r, "max_speed_mps", spec.max_speed_mps, 5);
  spec.max_turn_radps = positive(r, "max_turn_radps", spec.max_turn_radps, 10);
  if (r.has("waypoints")) spec.waypoints_m = load_waypoints(r, "waypoints", plan);
  if (r.has("laser_fails_at_s")) spec.laser_fails_at_s = non_negative(r, "laser_fails_at_s", 0, 86400);
  return spec;
}

ObjectShape parse_shape(const YamlConfig& o) {
  const std::string s = o.get<std::string>("shape", "box");
  if (s == "box") return ObjectShape::kBox;
  if (s == "cylinder") return ObjectShape::kCylinder;
  if (s == "sphere") return ObjectShape::kSphere;
  o.fail("shape", "must be one of box, cylinder, sphere (got '" + s + "')");
}

WorldObject load_object(const YamlConfig& o, const WorldLoadOptions& options) {
  WorldObject obj;
  o.allow_only({"id", "class", "shape", "color", "size_m", "pose"});
  obj.id = o.require<int>("id");
  obj.object_class = o.require<std::string>("class");
  const auto& classes = options.object_classes;
  if (std::find(classes.begin(), classes.end(), obj.object_class) == classes.end()) {
    std::string list;
    for (const auto& c : classes) list += (list.empty() ? "" : ", ") + c;
    o.fail("class", "'" + obj.object_class + "' is not one of: " + list);
  }
  obj.shape = parse_shape(o);
  const auto color = require_numbers(o, "color", 3);
  for (int i = 0; i < 3; ++i) {
    if (color[i] < 0 || color[i] > 255) o.fail("color", "values must be within 0..255");
    obj.color_rgb[i] = uint8_t(std::lround(color[i]));
  }
  const auto size = require_numbers(o, "size_m", 3);
  obj.size_m = Eigen::Vector3d(size[0], size[1], size[2]);
  if ((obj.size_m.array() <= 0.0).any()) o.fail("size_m", "must be > 0");
  const auto pose = require_numbers(o, "pose", 4);
  obj.center_m = Eigen::Vector3d(pose[0], pose[1], pose[2]);
  obj.yaw_rad = normalize_angle(pose[3]);
  return obj;
}

}  // namespace

const char* to_string(ObjectShape shape) {
  switch (shape) {
    case ObjectShape::kBox:
      return "box";
    case ObjectShape::kCylinder:
      return "cylinder";
    case ObjectShape::kSphere:
      return "sphere";
  }
  return "?";
}

FloorPlan load_floor_plan_image(const std::string& image_path, double resolution_m, const Eigen::Vector2d& origin_m) {
  if (!std::filesystem::exists(image_path)) throw InputError(image_path + ": cannot open file");
  const cv::Mat img = cv::imread(image_path, cv::IMREAD_GRAYSCALE);
  if (img.empty()) throw InputError(image_path + ": not a readable PGM/PNG image");
  const int w = img.cols, h = img.rows;
  std::vector<uint8_t> walls(size_t(w) * size_t(h), 0);
  for (int r = 0; r < h; ++r) {
    const uint8_t* px = img.ptr<uint8_t>(h - 1 - r);  // image top row = grid top row
    for (int c = 0; c < w; ++c) walls[size_t(r) * size_t(w) + size_t(c)] = px[c] < 128 ? 1 : 0;
  }
  return FloorPlan(w, h, resolution_m, origin_m, std::move(walls));
}

WorldFile load_world_file(const std::string& yaml_path, const WorldLoadOptions& options) {
  const YamlConfig root = YamlConfig::load(yaml_path);
  root.allow_only({"name", "map", "sim", "sensors", "robots", "objects", "radio"});
  WorldFile out;
  World& world = out.world;
  world.name = root.get<std::string>("name", std::filesystem::path(yaml_path).stem().string());
  const YamlConfig map = root["map"];
  map.allow_only({"image", "resolution_m", "origin_m", "wall_height_m"});
  const std::string image = map.require<std::string>("image");
  const double resolution_m = positive(map, "resolution_m", 0.05, 1);
  const auto origin = map.has("origin_m") ? require_numbers(map, "origin_m", 2) : std::vector<double>{0.0, 0.0};
  world.wall_height_m = positive(map, "wall_height_m", world.wall_height_m, 20);
  std::filesystem::path image_path(image);
  if (image_path.is_relative()) image_path = std::filesystem::path(yaml_path).parent_path() / image_path;
  try {
    world.floor_plan = load_floor_plan_image(image_path.string(), resolution_m, Eigen::Vector2d(origin[0], origin[1]));
  } catch (const InputError& e) {
    map.fail("image", std::string("cannot be loaded: ") + e.what());
  }
  const bool drive_given = load_sim(root, out.sim);

  const double radius_m = out.sim.robot_radius_m;
  std::set<int> robot_ids;
  for (const YamlConfig& r : root.sequence("robots")) {
    world.robots.push_back(load_robot(r, world.floor_plan, std::max(options.robot_radius_m, radius_m)));
    const RobotSpec& added = world.robots.back();
    if (!robot_ids.insert(added.id.value).second) r.fail("id", "is a duplicate");
    for (size_t i = 0; i + 1 < world.robots.size(); ++i) {
      if ((world.robots[i].T_world_start.translation() - added.T_world_start.translation()).norm() < 2.0 * radius_m)
        r.fail("start", "overlaps the start of " + to_string(world.robots[i].id));
    }
  }
  if (world.robots.empty()) root.fail("robots", "must list at least one robot");
  world.radio = load_radio(root, world);
  // Waypoints written in the world file drive the robots unless `sim: {drive: commands}` says not.
  const bool any_waypoints =
      std::any_of(world.robots.begin(), world.robots.end(), [](const RobotSpec& r) { return !r.waypoints_m.empty(); });
  if (!drive_given) out.sim.drive_mode = any_waypoints ? DriveMode::kWaypoints : DriveMode::kCommands;
  if (!options.routes_path.empty()) load_routes_file(options.routes_path, &out);
  if (root.has("objects")) {
    std::set<int> object_ids;
    for (const YamlConfig& o : root.sequence("objects")) {
      world.objects.push_back(load_object(o, options));
      if (!object_ids.insert(world.objects.back().id).second) o.fail("id", "is a duplicate");
    }
  }
  return out;
}

void load_routes_file(const std::string& routes_path, WorldFile* file) {
  const YamlConfig root = YamlConfig::load(routes_path);
  root.allow_only({"routes"});
  std::vector<std::vector<Eigen::Vector2d>> routes(file->world.robots.size());
  std::vector<bool> listed(routes.size(), false);
  for (const YamlConfig& r : root.sequence("routes")) {
    r.allow_only({"robot", "waypoints"});
    const int id = r.require<int>("robot");
    const auto& robots = file->world.robots;
    const auto it = std::find_if(robots.begin(), robots.end(), [&](const RobotSpec& s) { return s.id.value == id; });
    if (it == robots.end()) {
      std::string ids;
      for (const RobotSpec& s : robots) ids += (ids.empty() ? "" : ", ") + std::to_string(s.id.value);
      r.fail("robot",
             "is " + std::to_string(id) + ": world '" + file->world.name + "' has no such robot (it has " + ids + ")");
    }
    const size_t index = size_t(it - robots.begin());
    if (listed[index]) r.fail("robot", "is " + std::to_string(id) + ", which has a route already");
    listed[index] = true;
    routes[index] = load_waypoints(r, "waypoints", file->world.floor_plan);
  }
  for (size_t i = 0; i < routes.size(); ++i) file->world.robots[i].waypoints_m = std::move(routes[i]);
  file->sim.drive_mode = DriveMode::kWaypoints;
}

SE2 entry_hint_guess(const World& world, size_t index, double sigma_xy_m, double sigma_yaw_rad) {
  const double a = 2.0 * M_PI * double(index) / double(world.robots.size());
  return world.robots.at(index).T_world_start *
         SE2(sigma_xy_m * std::cos(a), sigma_xy_m * std::sin(a), 0.5 * sigma_yaw_rad);
}

std::optional<EntryHintSigmas> parse_entry_hint_sigmas(const std::string& text) {
  EntryHintSigmas s;
  char comma = 0;
  std::istringstream in(text);
  if (!(in >> s.xy_m >> comma >> s.yaw_deg) || comma != ',' || !(in >> std::ws).eof() || !(s.xy_m > 0) ||
      !(s.yaw_deg > 0))
    return std::nullopt;
  return s;
}

}  // namespace cairn::sim
