#include "sim/simulator.h"

#include <algorithm>
#include <cmath>

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
                                 std::mt19937_64(stream_seed(options_.seed, id, 2)), Trajectory{}});
  }
  if (options_.enable_camera) {
    renderer_ =
        std::make_unique<RgbdRenderer>(options_.camera, world_.floor_plan, world_.wall_height_m, world_.objects);
  }
}

bool Simulator::done() const {
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
      out.scans.push_back({r.spec.id, laser_.scan(world_.floor_plan, r.T_world_base, out.stamp_ns, r.laser_rng)});
    }
  }
  if (renderer_ && due(out.stamp_ns, camera_period_ns_, &next_camera_ns_)) {
    for (RobotState& r : robots_) {
      out.frames.push_back({r.spec.id, renderer_->render(r.T_world_base, out.stamp_ns, r.camera_rng)});
    }
  }
  advance();
  return out;
}

void Simulator::advance() {
  const double dt_s = ns_to_sec(dt_ns_);
  bool all_finished = true;
  for (RobotState& r : robots_) {
    const VelocityCommand cmd = r.follower.update(r.T_world_base);
    const SE2 next = integrate_unicycle(r.T_world_base, cmd.linear_mps, cmd.angular_radps, dt_s);
    r.odometry.add_step(r.T_world_base.between(next), dt_s);
    r.T_world_base = next;
    all_finished = all_finished && r.follower.finished();
  }
  ++step_index_;
  if (all_finished && all_finished_ns_ < 0) all_finished_ns_ = now_ns();
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
  return r == nullptr || r->follower.finished();
}

}  // namespace cairn::sim
