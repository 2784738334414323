#pragma once
// The worlds of bench_merger_scale: a random building of 8 m rooms that robots wander through
// (--loops: noisy odometry, 360-beam scans ray-cast in the building), and the small synthetic
// keyframes of the default configuration.
#include <random>
#include <vector>

#include "base_station/core/synthetic_world_test_util.h"
#include "common/keyframe.h"

namespace cairn::bench {

constexpr double kRoomM = 8.0;
constexpr int kRoomsX = 10, kRoomsY = 6;

/// A building of kRoomsX x kRoomsY rooms. Each inner wall is open, has a 1.6 m door, or is closed;
/// some rooms hold a pillar. pass[x][y][0] / [1]: can pass from room (x, y) to (x + 1, y) / (x, y + 1).
struct Building {
  std::vector<base::testing::Segment> walls;
  bool pass[kRoomsX][kRoomsY][2] = {};
};
Building make_building(std::mt19937* rng);

/// A robot of the --loops world: goes from room centre to a random passable neighbour's centre.
struct Walker {
  int x = 0, y = 0;
  std::vector<SE2> plan;  ///< remaining true poses to visit (0.5 m apart)
  SE2 true_pose, local_pose;
  int seq = 0;
};

/// The next keyframe of walker w (noisy odometry; scan ray-cast in the building).
Keyframe next_loop_keyframe(const Building& b, std::mt19937* rng, RobotId robot, Walker* w);
/// A keyframe of the default configuration: a small synthetic scan (a wavy circular room).
Keyframe make_keyframe(RobotId robot, int seq, const SE2& prev, const SE2& pose);

}  // namespace cairn::bench
