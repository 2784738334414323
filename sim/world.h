#pragma once
// The static description of a simulated mission: the floor plan (walls extruded to wall_height_m),
// the robots with their start poses (and, optionally, scripted waypoint routes), and the objects of
// interest (victims, hazards, exits) as coloured 3D primitives. Loaded from a YAML file plus a
// floor-plan image (PGM or PNG; pixels darker than 128 are walls). See worlds/office.yaml for the
// format; scripted routes live apart in a routes file (worlds/routes/office.yaml).
#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "common/ids.h"
#include "common/se2.h"
#include "sim/floor_plan.h"
#include "sim/radio_model.h"
#include "sim/sim_options.h"

namespace cairn::sim {

enum class ObjectShape { kBox, kCylinder, kSphere };
const char* to_string(ObjectShape shape);

/// An object of interest. size_m: box = (x, y, z) extents in the object frame; cylinder (vertical
/// axis) = (diameter, diameter, height); sphere = (diameter, diameter, diameter).
struct WorldObject {
  int id = 0;
  std::string object_class;  ///< "victim", "hazard", "exit", ...
  ObjectShape shape = ObjectShape::kBox;
  std::array<uint8_t, 3> color_rgb{{255, 0, 0}};
  Eigen::Vector3d size_m = Eigen::Vector3d::Constant(0.5);
  Eigen::Vector3d center_m = Eigen::Vector3d::Zero();  ///< world frame, z = height of the centre
  double yaw_rad = 0.0;                                ///< rotation about the vertical axis
};

/// A robot and the scripted route it drives in DriveMode::kWaypoints.
struct RobotSpec {
  RobotId id;
  SE2 T_world_start;
  double max_speed_mps = 0.6;
  double max_turn_radps = 1.2;
  std::vector<Eigen::Vector2d> waypoints_m;  ///< world frame, driven in order
  /// The laser breaks (dust, smoke, a knock) this many seconds into the mission and sends nothing
  /// from then on; odometry and camera go on. Negative: never.
  double laser_fails_at_s = -1.0;
};

struct World {
  std::string name;
  FloorPlan floor_plan;
  double wall_height_m = 2.0;
  std::vector<RobotSpec> robots;
  std::vector<WorldObject> objects;
  RadioOptions radio;  ///< the simulated radio (used when the mission turns it on)
};

/// A world file holds both the World and the simulator settings (sections `sim` and `sensors`).
struct WorldFile {
  World world;
  SimOptions sim;
};

/// The entry hint a rescue team would give for robot `index` (> 0) of `world`: its true start off
/// by about one sigma, in a different direction for each robot, and half a sigma of heading.
SE2 entry_hint_guess(const World& world, size_t index, double sigma_xy_m, double sigma_yaw_rad);

/// The sigmas of `--entry-hints SIGMA_XY_M,SIGMA_YAW_DEG` (cairn_mission, bench_link_replay); nullopt
/// unless both are there and positive.
struct EntryHintSigmas {
  double xy_m = 0.0;
  double yaw_deg = 0.0;
};
std::optional<EntryHintSigmas> parse_entry_hint_sigmas(const std::string& text);

/// Loads a world YAML (and the image it names, relative to the YAML file). Throws InputError naming
/// the file and key for a missing/malformed file or an invalid value (non-positive resolution, a
/// start pose inside or too close to a wall, overlapping starts, an unknown object class or shape,
/// NaN, ...). Drive mode: `sim: {drive: commands|waypoints}` when given; otherwise kWaypoints if any
/// robot has `waypoints`, else kCommands. options.routes_path, when set, is applied last
/// (load_routes_file).
WorldFile load_world_file(const std::string& yaml_path, const WorldLoadOptions& options = {});

/// Reads scripted routes (`routes: - {robot: 0, waypoints: [[x, y], ...]}`) into `file`: they
/// replace every robot's waypoints (a robot not listed gets none) and set the drive mode to
/// kWaypoints. Throws InputError naming the routes file and key for a robot the world does not have,
/// a robot listed twice, or a waypoint that is malformed, off the map or inside a wall; `file` is
/// unchanged then.
void load_routes_file(const std::string& routes_path, WorldFile* file);

/// Loads a floor-plan image (PGM/PNG) into a FloorPlan; throws InputError naming the file.
FloorPlan load_floor_plan_image(const std::string& image_path, double resolution_m, const Eigen::Vector2d& origin_m);

}  // namespace cairn::sim
