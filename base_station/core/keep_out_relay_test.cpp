#include "base_station/core/keep_out_relay.h"

#include <gtest/gtest.h>

#include <cmath>

namespace cairn::base {
namespace {

KeepOutArea area(uint32_t id, double x0, double y0, double x1, double y1) {
  KeepOutArea a;
  a.id = id;
  a.min_m = {x0, y0};
  a.max_m = {x1, y1};
  return a;
}

KeepOutRobotState linked_robot(const SE2& T_global_local) {
  KeepOutRobotState r;
  r.robot = RobotId(2);
  r.linked = true;
  r.T_global_local = T_global_local;
  return r;
}

TEST(KeepOutRelay, ALinkedRobotIsToldEachChangeInItsOwnFrameAndAnUnlinkedOneNothing) {
  KeepOutRelay relay;
  const SE2 T_global_local(10.0, 0.0, M_PI / 2);  // the robot's x axis points north on the merged map
  KeepOutRobotState robot = linked_robot(T_global_local);
  const std::vector<KeepOutArea> one{area(1, 12.0, 3.0, 14.0, 4.0)};
  EXPECT_FALSE(relay.due(robot, {}, 0.0)) << "no areas drawn: nothing to tell";
  KeepOutRobotState unlinked = robot;
  unlinked.linked = false;
  EXPECT_FALSE(relay.due(unlinked, one, 0.0)) << "nobody knows where an unlinked robot's frame lies";

  const auto first = relay.due(robot, one, 0.0);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->robot, RobotId(2));
  EXPECT_EQ(first->version, 1u);
  ASSERT_EQ(first->areas.size(), 1u);
  EXPECT_EQ(first->areas[0].id, 1u);
  // Merged-map point (13, 3.5) is 3.5 m along the robot's x axis and 3 m to its right (-y).
  EXPECT_TRUE(first->areas[0].contains({3.5, -3.0}));
  EXPECT_FALSE(first->areas[0].contains({3.0, 3.5}));
  relay.mark_sent(robot, one, *first, 0.0);
  EXPECT_EQ(relay.sent_version(RobotId(2)), 1u);
  robot.held_version = 1;
  EXPECT_FALSE(relay.due(robot, one, 60.0)) << "held: nothing new to say";

  const std::vector<KeepOutArea> two{one[0], area(2, 0.0, 0.0, 1.0, 1.0)};
  const auto second = relay.due(robot, two, 61.0);
  ASSERT_TRUE(second);
  EXPECT_EQ(second->version, 2u);
  EXPECT_EQ(second->areas.size(), 2u);
  relay.mark_sent(robot, two, *second, 61.0);
  robot.held_version = 2;
  const auto cleared = relay.due(robot, {}, 62.0);
  ASSERT_TRUE(cleared) << "clearing every area must reach the robot too";
  EXPECT_EQ(cleared->version, 3u);
  EXPECT_TRUE(cleared->areas.empty());
}

TEST(KeepOutRelay, AMovedFrameIsSentAgainButJitterIsNot) {
  KeepOutRelay relay;
  KeepOutRobotState robot = linked_robot(SE2(0.0, 0.0, 0.0));
  const std::vector<KeepOutArea> areas{area(1, 2.0, 2.0, 3.0, 3.0)};
  relay.mark_sent(robot, areas, *relay.due(robot, areas, 0.0), 0.0);
  robot.held_version = 1;
  robot.T_global_local = SE2(0.1, 0.05, 0.01);
  EXPECT_FALSE(relay.due(robot, areas, 1.0)) << "a re-optimisation's few centimetres change no plan";
  robot.T_global_local = SE2(0.5, 0.0, 0.0);
  const auto moved = relay.due(robot, areas, 2.0);
  ASSERT_TRUE(moved);
  EXPECT_EQ(moved->version, 2u);
  EXPECT_TRUE(moved->areas[0].contains({2.0, 2.5})) << "merged (2.5, 2.5) is local (2.0, 2.5) now";
  robot.T_global_local = SE2(0.0, 0.0, 0.05);
  EXPECT_TRUE(relay.due(robot, areas, 3.0)) << "a turn of 0.05 rad moves a corner 10 m out by 0.5 m";
}

TEST(KeepOutRelay, AVersionTheRobotDoesNotReportHoldingIsSentAgainAfterAWhile) {
  KeepOutRelay relay;
  KeepOutRobotState robot = linked_robot(SE2(0.0, 0.0, 0.0));
  const std::vector<KeepOutArea> areas{area(1, 2.0, 2.0, 3.0, 3.0)};
  relay.mark_sent(robot, areas, *relay.due(robot, areas, 0.0), 0.0);
  EXPECT_FALSE(relay.due(robot, areas, 4.0)) << "give the radio time";
  const auto again = relay.due(robot, areas, 6.0);
  ASSERT_TRUE(again) << "the robot never said it holds version 1";
  EXPECT_EQ(again->version, 1u) << "the same version again, not a new one";
  relay.mark_sent(robot, areas, *again, 6.0);
  EXPECT_FALSE(relay.due(robot, areas, 8.0));
  robot.held_version = 1;
  EXPECT_FALSE(relay.due(robot, areas, 60.0));
}

}  // namespace
}  // namespace cairn::base
