#pragma once
// Options of the simulator's components, with defaults. One plain struct per component; the world
// loader (world.h) maps the YAML `sim:` and `sensors:` sections onto them and validates them.
#include <cstdint>
#include <string>
#include <vector>

namespace cairn::sim {

/// Wheel odometry noise. Errors accumulate as a random walk whose VARIANCE grows linearly with the
/// distance / rotation travelled, so the drift does not depend on the step rate:
///   per step: sd_trans = trans_noise_per_m * sqrt(d_m),
///             sd_rot   = sqrt(rot_noise_rad_per_m^2 * d_m + rot_noise_per_rad^2 * |dyaw_rad|).
/// E.g. trans_noise_per_m = 0.05 gives 0.05 m sd after 1 m and 0.5 m after 100 m.
struct OdometryOptions {
  double rate_hz = 20.0;
  double trans_noise_per_m = 0.05;
  double rot_noise_rad_per_m = 0.02;
  double rot_noise_per_rad = 0.05;
};

/// 2D laser at the base origin (T_base_laser = identity). For a 360 deg field of view the beams are
/// angle_min = -pi, increment = 2 pi / beams; otherwise they span [-fov/2, +fov/2] inclusive.
struct LaserOptions {
  double rate_hz = 10.0;
  int beams = 360;
  double fov_deg = 360.0;
  double max_range_m = 12.0;
  double min_range_m = 0.05;
  double noise_sd_m = 0.01;
  /// Intensity of a return: the walls and rubble, and the retro-reflective tape every robot of the
  /// team carries around its body (what lets an agent leave its teammates out of its SLAM).
  float surface_intensity = 0.3f;
  float teammate_intensity = 1.0f;
};

/// Forward-looking RGB-D camera at height_m above the base origin, pitched down by pitch_deg.
struct CameraOptions {
  double rate_hz = 2.0;
  int width = 320;
  int height = 240;
  double hfov_deg = 70.0;
  double max_depth_m = 6.0;  ///< depth pixels beyond this read 0 (colour is still rendered)
  double height_m = 0.5;
  double pitch_deg = 0.0;         ///< positive tilts the camera down
  double forward_offset_m = 0.0;  ///< camera x in the base frame
  double depth_noise_sd_m = 0.005;
  double rgb_noise_sd = 0.0;     ///< Gaussian noise on RGB values (0..255 scale); 0 = off
  double render_range_m = 25.0;  ///< walls further than this (horizontally) are not drawn
};

/// How the simulated robots are driven. kCommands: each robot obeys the last velocity command given
/// to it (Simulator::set_command, the shape of ROS's cmd_vel), zero until told. kWaypoints: each
/// robot drives its scripted route (RobotSpec::waypoints_m) with the WaypointFollower.
enum class DriveMode { kCommands, kWaypoints };
inline const char* to_string(DriveMode mode) { return mode == DriveMode::kCommands ? "commands" : "waypoints"; }

/// Everything the Simulator needs besides the World.
struct SimOptions {
  uint64_t seed = 7;
  double dt_s = 0.05;
  double duration_s = 120.0;
  double settle_time_s = 1.0;  ///< mission ends this long after the last robot finished / was declared done
  DriveMode drive_mode = DriveMode::kCommands;
  double robot_radius_m = 0.2;  ///< every robot is a disc: collisions, and what the other robots' lasers see
  /// false: lasers see through the other robots (to measure what they cost the robots' SLAM).
  bool lasers_see_robots = true;
  /// The cameras see the other robots: a cylinder of robot_radius_m and robot_height_m in its
  /// marker's colour (common/robot_markers.h; grey for a robot without one).
  bool cameras_see_robots = true;
  double robot_height_m = 0.4;
  bool enable_laser = true;
  bool enable_camera = true;
  OdometryOptions odometry;
  LaserOptions laser;
  CameraOptions camera;
};

/// What the loader accepts and checks.
struct WorldLoadOptions {
  std::vector<std::string> object_classes = {"victim", "hazard", "exit"};
  /// Start poses closer than this (or than the world's sim.robot_radius_m, whichever is larger) to a
  /// wall are rejected.
  double robot_radius_m = 0.2;
  /// Scripted routes (YAML `routes: - {robot: 0, waypoints: [[x, y], ...]}`): when not empty, they
  /// replace every robot's waypoints (a robot not listed gets none) and the drive mode is kWaypoints.
  std::string routes_path;
};

}  // namespace cairn::sim
