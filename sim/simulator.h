#pragma once
// The multi-robot simulator core: advances every robot of a World by one fixed step on a simulated
// clock and returns the sensor readings due at that step (odometry, 2D laser, RGB-D). Pure and
// deterministic for a seed: no threads, no wall clock, no I/O. Each robot and sensor draws noise
// from its own random stream, so enabling one sensor never changes another's readings.
// Driving (SimOptions::drive_mode): in kCommands (the default) each robot obeys the last velocity
// command given through set_command() (clamped to its limits; zero until told), like a real robot's
// cmd_vel; in kWaypoints each robot drives its scripted route with the WaypointFollower.
// Robots are discs of SimOptions::robot_radius_m. A step that would put a disc into a wall cell, or
// (kCommands only: scripted routes ignore each other) onto another robot's disc, is not taken (pose
// and odometry stay; robots move in ascending id order, each against the others' current poses);
// rotating in place is always allowed. collisions() counts contact episodes: one starts when a
// robot that was moving freely is blocked, and ends at its next step that moves it. Each robot's
// laser also sees the other robots (circles of the same radius).
// Timing: step k has stamp k * dt (integer nanoseconds). step() first records ground truth and
// emits the readings of the state at that stamp, then integrates the motion to the next stamp.
// A sensor with rate f is due at the first step whose stamp reaches its next due time (multiples
// of 1/f from 0). The mission ends at duration_s, or settle_time_s after every robot has reached
// its final waypoint (kWaypoints) / has been declared done through set_robot_done() (kCommands).
#include <memory>
#include <random>
#include <vector>

#include "common/ids.h"
#include "common/laser_scan.h"
#include "common/sensors.h"
#include "common/trajectory.h"
#include "sim/diff_drive.h"
#include "sim/laser_sim.h"
#include "sim/rgbd_renderer.h"
#include "sim/world.h"

namespace cairn::sim {

/// Ground-truth object ids of the robots' bodies in rendered frames: this plus the robot id.
inline constexpr int kRobotBodyObjectIdBase = 1000;

template <typename Reading>
struct RobotReading {
  RobotId robot;
  Reading reading;
};

/// Readings produced by one step, each vector in ascending robot id order.
struct SimStep {
  StampNs stamp_ns = 0;
  std::vector<RobotReading<OdometryReading>> odometry;
  std::vector<RobotReading<LaserScan>> scans;
  std::vector<RobotReading<RgbdFrame>> frames;
};

class Simulator {
 public:
  Simulator(const World& world, const SimOptions& options);

  bool done() const;
  /// Emits the readings due at the current stamp, then advances all robots by dt.
  SimStep step();

  /// kCommands: the robot holds this command from the next step on, clamped to its max_speed_mps
  /// (both directions) and max_turn_radps. False, and nothing changes, for a NaN/inf command, an
  /// unknown robot, or in kWaypoints (the route drives).
  bool set_command(RobotId robot, const VelocityCommand& command);
  /// The command the robot holds now (kCommands; zero for an unknown robot or in kWaypoints).
  VelocityCommand command(RobotId robot) const;
  /// kCommands: an agent says its robot is home (or not any more). Unknown ids are ignored.
  void set_robot_done(RobotId robot, bool done);
  /// Contact episodes of this robot with walls or other robots so far (0 for an unknown id).
  int collisions(RobotId robot) const;
  double robot_radius_m() const { return options_.robot_radius_m; }
  DriveMode drive_mode() const { return options_.drive_mode; }

  StampNs now_ns() const { return StampNs(step_index_) * dt_ns_; }
  StampNs dt_ns() const { return dt_ns_; }
  const World& world() const { return world_; }
  const SimOptions& options() const { return options_; }

  std::vector<RobotId> robot_ids() const;
  /// The robot's true pose now; its start pose (the origin of its odom frame) in the world.
  /// Unknown ids give identity / an empty trajectory.
  SE2 true_pose(RobotId robot) const;
  SE2 T_world_start(RobotId robot) const;
  /// True poses at every stamp emitted so far.
  const Trajectory& ground_truth(RobotId robot) const;
  /// kWaypoints: reached its final waypoint; kCommands: declared done. True for an unknown id.
  bool robot_finished(RobotId robot) const;
  const std::vector<WorldObject>& objects() const { return world_.objects; }
  const RgbdRenderer& renderer() const { return *renderer_; }
  const LaserSimulator& laser() const { return laser_; }

 private:
  struct RobotState {
    RobotSpec spec;
    SE2 T_world_base;
    WaypointFollower follower;
    OdometryIntegrator odometry;
    std::mt19937_64 laser_rng;
    std::mt19937_64 camera_rng;
    Trajectory ground_truth;
    VelocityCommand command;     ///< kCommands: the last accepted command
    bool declared_done = false;  ///< kCommands: set_robot_done
    bool blocked = false;        ///< in a contact episode
    int collisions = 0;
  };
  const RobotState* find(RobotId robot) const;  ///< nullptr for an unknown id
  RobotState* find(RobotId robot);
  static bool due(StampNs now_ns, StampNs period_ns, StampNs* next_due_ns);
  /// True when the robot's disc at `next` touches a wall or comes onto another robot's disc (a move
  /// that takes it further from a robot it already overlaps is allowed).
  bool blocked(const RobotState& robot, const SE2& next) const;
  std::vector<Eigen::Vector2d> other_robots_m(const RobotState& robot) const;
  /// The other robots' bodies as the cameras see them (SimOptions::cameras_see_robots).
  std::vector<WorldObject> other_robot_bodies(const RobotState& robot) const;
  void advance();

  World world_;
  SimOptions options_;
  StampNs dt_ns_;
  StampNs duration_ns_;
  StampNs odometry_period_ns_, laser_period_ns_, camera_period_ns_;
  StampNs next_odometry_ns_ = 0, next_laser_ns_ = 0, next_camera_ns_ = 0;
  int64_t step_index_ = 0;
  StampNs all_finished_ns_ = -1;    ///< first stamp at which every robot had finished / was done
  std::vector<RobotState> robots_;  ///< ascending robot id
  LaserSimulator laser_;
  std::unique_ptr<RgbdRenderer> renderer_;
};

}  // namespace cairn::sim
