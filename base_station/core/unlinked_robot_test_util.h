#pragma once
// Test-only: a mapper with a robot it can never link. Robot 0 maps the room; robot 1 drives east
// along a corridor elsewhere from (2, 0.75) and sees a victim at (6, 1) in the world, which is
// (4, 0.25) in robot 1's own frame.
#include <vector>

#include "base_station/core/multi_robot_mapper.h"
#include "base_station/core/synthetic_world_test_util.h"

namespace cairn::base::testing {

struct UnlinkableRobot {
  MultiRobotMapper mapper;
  std::vector<SE2> corridor;
  UnlinkableRobot() {
    const std::vector<Segment> walls = {{{0, 0}, {30, 0}}, {{0, 1.5}, {30, 1.5}}};
    for (int i = 0; i < 10; ++i) corridor.push_back(SE2(2 + i, 0.75, 0));
    for (const Keyframe& k : make_keyframes(RobotId(0), left_path(), room_walls())) mapper.add_keyframe(k);
    for (const Keyframe& k : make_keyframes(RobotId(1), corridor, walls)) mapper.add_keyframe(k);
    mapper.add_object(make_object(ObjectId{RobotId(1), 0}, "victim", {6.0, 1.0, 0.2}, 3, corridor[3]));
    mapper.optimize();
  }
};

}  // namespace cairn::base::testing
