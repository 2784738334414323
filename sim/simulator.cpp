#include "sim/simulator.h"

#include <algorithm>
#include <cmath>

#include "common/robot_markers.h"

namespace cairn::sim {
namespace {

// Independent, reproducible stream per (seed, robot, sensor).
uint64_t stream_seed(uint64_t seed, int robot, int sensor) {
  std::seed_seq seq{uint32_t(seed), uint32_t(seed >> 32), uint32_t(robot), uint32_t(sensor)};
  uint32_t words[2];
  seq.generate(words, words + 2);
  return (uint64_t(words[0]) << 32) | words[1];
}

StampNs period_ns(double rate_hz) { return std::max<StampNs>(1, sec_to_ns(1.0 / rate_hz)); }

}  // namespace

Simulator::Simulator(const World& world, const SimOptions& options)
    : world_(world),
      options_(options),
      dt_ns_(std::max<StampNs>(1, sec_to_ns(options.dt_s))),
      duration_ns_(sec_to_ns(options.duration_s)),
      odometry_period_ns_(period_ns(options.odometry.rate_hz)),
      laser_period_ns_(period_ns(options.laser.rate_hz)),
      camera_period_ns_(period_ns(options.camera.rate_hz)),
      laser_(options.laser) {
  std::vector<RobotSpec> specs = world_.robots;
  std::sort(specs.begin(), specs.end(), [](const RobotSpec& a, const RobotSpec& b) { return a.id < b.id; });
  for (const RobotSpec& spec : specs) {
    FollowerOptions follower;
    follower.max_speed_mps = spec.max_speed_mps;
    follower.max_turn_radps = spec.max_turn_radps;
    const int id = spec.id.value;
    robots_.push_back(RobotState{spec, spec.T_world_start,
                                 WaypointFollower(spec.T_world_start.translation(), spec.waypoints_m, follower),
                                 OdometryIntegrator(options_.odometry, stream_seed(options_.seed, id, 0)),
                                 std::mt19937_64(stream_seed(options_.seed, id, 1)),
                                 std::mt19937_64(stream_seed(options_.seed, id, 2)), Trajectory{}, VelocityCommand{},
                                 /*declared_done=*/false, /*blocked=*/false, /*collisions=*/0});
  }
  if (options_.enable_camera) {
    renderer_ =
        std::make_unique<RgbdRenderer>(options_.camera, world_.floor_plan, world_.wall_height_m, world_.objects);
  }
}

bool Simulator::done() const {
  // kWaypoints: all_finished_ns_ is set when every route is driven; kCommands: by set_robot_done.
  if (now_ns() > duration_ns_) return true;
  return all_finished_ns_ >= 0 && now_ns() > all_finished_ns_ + sec_to_ns(options_.settle_time_s);
}

bool Simulator::due(StampNs now_ns, StampNs period_ns, StampNs* next_due_ns) {
  if (now_ns < *next_due_ns) return false;
  // Skip due times that fell between steps (sensor faster than the step rate).
  while (*next_due_ns <= now_ns) *next_due_ns += period_ns;
  return true;
}

SimStep Simulator::step() {
  SimStep out;
  out.stamp_ns = now_ns();
  for (RobotState& r : robots_) r.ground_truth.push_back({out.stamp_ns, r.T_world_base});
  if (due(out.stamp_ns, odometry_period_ns_, &next_odometry_ns_)) {
    for (const RobotState& r : robots_) {
      const OdometryReading odo{out.stamp_ns, r.odometry.T_odom_base(), r.odometry.linear_mps(),
                                r.odometry.angular_radps()};
      out.odometry.push_back({r.spec.id, odo});
    }
  }
  if (options_.enable_laser && due(out.stamp_ns, laser_period_ns_, &next_laser_ns_)) {
    for (RobotState& r : robots_) {
      if (r.spec.laser_fails_at_s >= 0 && out.stamp_ns >= StampNs(r.spec.laser_fails_at_s * 1e9)) continue;  // broken
      const std::vector<Eigen::Vector2d> others =
          options_.lasers_see_robots ? other_robots_m(r) : std::vector<Eigen::Vector2d>{};
      out.scans.push_back({r.spec.id, laser_.scan(world_.floor_plan, r.T_world_base, out.stamp_ns, r.laser_rng, others,
                                                  options_.robot_radius_m)});
    }
  }
  if (renderer_ && due(out.stamp_ns, camera_period_ns_, &next_camera_ns_)) {
    for (RobotState& r : robots_) {
      out.frames.push_back(
          {r.spec.id, renderer_->render(r.T_world_base, out.stamp_ns, r.camera_rng, nullptr, other_robot_bodies(r))});
    }
  }
  advance();
  return out;
}

void Simulator::advance() {
  const double dt_s = ns_to_sec(dt_ns_);
  const bool waypoints = options_.drive_mode == DriveMode::kWaypoints;
  bool all_finished = true;
  for (RobotState& r : robots_) {
    const VelocityCommand cmd = waypoints ? r.follower.update(r.T_world_base) : r.command;
    const SE2 next = integrate_unicycle(r.T_world_base, cmd.linear_mps, cmd.angular_radps, dt_s);
    // Turning in place never changes the disc, so it is never blocked.
    const bool moves = next.translation() != r.T_world_base.translation();
    if (moves && blocked(r, next)) {
      if (!r.blocked) ++r.collisions;
      r.blocked = true;
      r.odometry.add_step(SE2(), dt_s);  // the wheels did not turn: odometry stays with the truth
    } else {
      if (moves) r.blocked = false;
      r.odometry.add_step(r.T_world_base.between(next), dt_s);
      r.T_world_base = next;
    }
    all_finished = all_finished && r.follower.finished();
  }
  ++step_index_;
  if (waypoints && all_finished && all_finished_ns_ < 0) all_finished_ns_ = now_ns();
}

bool Simulator::blocked(const RobotState& robot, const SE2& next) const {
  const double radius_m = options_.robot_radius_m;
  const Eigen::Vector2d p = next.translation();
  if (world_.floor_plan.wall_at(p) || !world_.floor_plan.disc_free(p, radius_m)) return true;
  // Scripted routes were drawn without the other robots in mind (two_robots_meet drives them
  // through each other on purpose): in waypoint mode robots only block on walls.
  if (options_.drive_mode == DriveMode::kWaypoints) return false;
  for (const RobotState& other : robots_) {
    if (&other == &robot) continue;
    const Eigen::Vector2d c = other.T_world_base.translation();
    const double after_m = (p - c).norm();
    if (after_m < 2.0 * radius_m && after_m < (robot.T_world_base.translation() - c).norm()) return true;
  }
  return false;
}

std::vector<Eigen::Vector2d> Simulator::other_robots_m(const RobotState& robot) const {
  std::vector<Eigen::Vector2d> out;
  for (const RobotState& other : robots_) {
    if (&other != &robot) out.push_back(other.T_world_base.translation());
  }
  return out;
}

std::vector<WorldObject> Simulator::other_robot_bodies(const RobotState& robot) const {
  std::vector<WorldObject> out;
  if (!options_.cameras_see_robots) return out;
  for (const RobotState& other : robots_) {
    if (&other == &robot) continue;
    WorldObject body;
    body.id = kRobotBodyObjectIdBase + other.spec.id.value;
    body.object_class = "robot";
    body.shape = ObjectShape::kCylinder;
    const std::optional<RobotMarker> marker = robot_marker(other.spec.id);
    body.color_rgb = marker ? marker->color_rgb : std::array<uint8_t, 3>{{110, 110, 110}};
    const double d_m = 2.0 * options_.robot_radius_m;
    body.size_m = Eigen::Vector3d(d_m, d_m, options_.robot_height_m);
    body.center_m = Eigen::Vector3d(other.T_world_base.x(), other.T_world_base.y(), 0.5 * options_.robot_height_m);
    body.yaw_rad = other.T_world_base.yaw();
    out.push_back(body);
  }
  return out;
}

bool Simulator::set_command(RobotId robot, const VelocityCommand& command) {
  RobotState* r = find(robot);
  if (r == nullptr || options_.drive_mode != DriveMode::kCommands) return false;
  if (!std::isfinite(command.linear_mps) || !std::isfinite(command.angular_radps)) return false;
  const double v = r->spec.max_speed_mps, w = r->spec.max_turn_radps;
  r->command.linear_mps = std::clamp(command.linear_mps, -v, v);
  r->command.angular_radps = std::clamp(command.angular_radps, -w, w);
  return true;
}

VelocityCommand Simulator::command(RobotId robot) const {
  const RobotState* r = find(robot);
  return r ? r->command : VelocityCommand{};
}

void Simulator::set_robot_done(RobotId robot, bool done) {
  RobotState* r = find(robot);
  if (r == nullptr) return;
  r->declared_done = done;
  if (options_.drive_mode != DriveMode::kCommands) return;
  const bool all_done =
      std::all_of(robots_.begin(), robots_.end(), [](const RobotState& s) { return s.declared_done; });
  if (!all_done) {
    all_finished_ns_ = -1;
  } else if (all_finished_ns_ < 0) {
    all_finished_ns_ = now_ns();
  }
}

int Simulator::collisions(RobotId robot) const {
  const RobotState* r = find(robot);
  return r ? r->collisions : 0;
}

std::vector<RobotId> Simulator::robot_ids() const {
  std::vector<RobotId> ids;
  for (const RobotState& r : robots_) ids.push_back(r.spec.id);
  return ids;
}

const Simulator::RobotState* Simulator::find(RobotId robot) const {
  for (const RobotState& r : robots_) {
    if (r.spec.id == robot) return &r;
  }
  return nullptr;
}

Simulator::RobotState* Simulator::find(RobotId robot) {
  return const_cast<RobotState*>(static_cast<const Simulator*>(this)->find(robot));
}

SE2 Simulator::true_pose(RobotId robot) const {
  const RobotState* r = find(robot);
  return r ? r->T_world_base : SE2();
}

SE2 Simulator::T_world_start(RobotId robot) const {
  const RobotState* r = find(robot);
  return r ? r->spec.T_world_start : SE2();
}

const Trajectory& Simulator::ground_truth(RobotId robot) const {
  static const Trajectory kEmpty;
  const RobotState* r = find(robot);
  return r ? r->ground_truth : kEmpty;
}

bool Simulator::robot_finished(RobotId robot) const {
  const RobotState* r = find(robot);
  if (r == nullptr) return true;
  return options_.drive_mode == DriveMode::kWaypoints ? r->follower.finished() : r->declared_done;
}

}  // namespace cairn::sim
