// The agent's Navigator driving a simulated robot (sim core: its laser, its disc that walls stop)
// with the true pose, no DDS: navigation failures that only show against the simulator's collision
// model (a disc that refuses a step touching a wall) are reproduced here deterministically.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "robot_agent/core/navigation/navigator.h"
#include "sim/simulator.h"
#include "sim/world.h"

namespace cairn {
namespace {

struct Outcome {
  NavState state = NavState::kDriving;
  double seconds = 0;
  double travelled_m = 0;
  int collisions = 0;
  Eigen::Vector2d end_m{0, 0};
};

// `attempts`: a goal that ends "stuck" is given again (as the base or the robot's own exploration
// gives it a new goal), from where the robot is.
Outcome drive_to(const sim::WorldFile& file, const SE2& start, const Eigen::Vector2d& goal_m, double max_s,
                 int attempts = 1) {
  sim::World world = file.world;
  world.robots.resize(1);
  world.robots[0].T_world_start = start;
  sim::SimOptions so = file.sim;
  so.enable_camera = false;
  so.drive_mode = sim::DriveMode::kCommands;
  so.duration_s = max_s + 10;
  sim::Simulator sim(world, so);
  const RobotId id = world.robots[0].id;
  agent::Navigator nav;
  nav.set_goal(agent::NavGoal{1, goal_m, GoalKind::kOwn, 0, {}});
  Outcome out;
  Eigen::Vector2d last = start.translation();
  uint32_t goal_id = 1;
  while (!sim.done() && ns_to_sec(sim.now_ns()) < max_s) {
    if (nav.state() == NavState::kStuck && int(goal_id) < attempts)
      nav.set_goal(agent::NavGoal{++goal_id, goal_m, GoalKind::kOwn, 0, {}});
    if (nav.state() != NavState::kDriving) break;
    const sim::SimStep step = sim.step();
    for (const auto& s : step.scans) {
      const SE2 pose = start.inverse() * sim.true_pose(id);  // the agent's local frame starts at its start
      sim.set_command(id, nav.update(step.stamp_ns, pose, s.reading));
    }
    const Eigen::Vector2d p = sim.true_pose(id).translation();
    out.travelled_m += (p - last).norm();
    last = p;
  }
  out.state = nav.state();
  out.seconds = ns_to_sec(sim.now_ns());
  out.collisions = sim.collisions(id);
  out.end_m = last;
  return out;
}

// Drives from `start_world` to each goal (world frame), prints each outcome, returns the failures.
int drive_everywhere(const sim::WorldFile& file, const Eigen::Vector2d& start_world,
                     const std::vector<Eigen::Vector2d>& goals_world, double max_s, int attempts = 1) {
  int failures = 0;
  for (int k = 0; k < 8; ++k) {
    const SE2 start(start_world, k * M_PI / 4);
    for (const Eigen::Vector2d& g : goals_world) {
      const Outcome o = drive_to(file, start, start.inverse() * g, max_s, attempts);
      std::printf("yaw %5.2f goal (%.2f,%.2f): %s in %.1f s, %.2f m, %d collisions, end (%.2f,%.2f)\n", start.yaw(),
                  g.x(), g.y(), to_string(o.state), o.seconds, o.travelled_m, o.collisions, o.end_m.x(), o.end_m.y());
      if (o.state != NavState::kReached || o.collisions > 0) ++failures;
    }
  }
  return failures;
}

TEST(NavigationInTheSimulator, ARobotBesideRubbleGetsAwayInEveryHeading) {
  // Robot 0 of the demo stopped for two minutes here (0.07 m from the rubble on its west, a
  // 0.75 m gap between two blocks): its safety stop counted rubble at its side as ahead, and the
  // arc to the lookahead cut a corner. Every heading, every way out must now be driven.
  const sim::WorldFile file = sim::load_world_file(std::string(CAIRN_SOURCE_DIR) + "/worlds/collapsed.yaml");
  const std::vector<Eigen::Vector2d> goals_world = {{2.62, 4.5}, {2.62, 0.5}, {5.0, 3.0}, {1.0, 3.5}};
  const int failures = drive_everywhere(file, {2.62, 1.85}, goals_world, 60);
  EXPECT_EQ(failures, 0);
}

TEST(NavigationInTheSimulator, ARobotInAPocketBetweenWallAndRubbleFindsTheWayOut) {
  // Robot 3 of a demo run sat here for ten minutes: a 0.6 m strip between the wall (north) and
  // rubble (south), closed at both ends by gaps narrower than its 0.4 m disc; the only way out is
  // the 1 m gap to the south-west. Every goal it was given there ended "stuck".
  const sim::WorldFile file = sim::load_world_file(std::string(CAIRN_SOURCE_DIR) + "/worlds/collapsed.yaml");
  const std::vector<Eigen::Vector2d> goals_world = {{3.5, 7.0}, {1.0, 6.0}, {5.0, 5.5}};
  EXPECT_EQ(drive_everywhere(file, {4.3, 7.86}, goals_world, 90, /*attempts=*/3), 0);
}

}  // namespace
}  // namespace cairn
