#include "dds/navigation_conversions.h"

#include <gtest/gtest.h>

#include <cmath>

namespace cairn::dds {
namespace {

TEST(NavigationConversions, CommandRoundTripsAndNaNIsRefusedByName) {
  const StampedCommand c{RobotId(3), 1500000000, {0.4, -0.7}, true};
  std::string error;
  const auto back = from_msg(to_msg(c), &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->robot, RobotId(3));
  EXPECT_EQ(back->stamp_ns, c.stamp_ns);
  EXPECT_DOUBLE_EQ(back->command.angular_radps, -0.7);
  EXPECT_TRUE(back->done);
  cairn_msgs::VelocityCommand bad = to_msg(c);
  bad.linear_mps(std::nan(""));
  EXPECT_FALSE(from_msg(bad, &error));
  EXPECT_NE(error.find("non-finite"), std::string::npos) << error;
  bad = to_msg(c);
  bad.robot_id(-2);
  EXPECT_FALSE(from_msg(bad, &error));
  EXPECT_NE(error.find("robot_id -2"), std::string::npos) << error;
}

TEST(NavigationConversions, GoalRoundTripsAndUnknownKindOrNaNIsRefused) {
  GoalMessage g;
  g.robot = RobotId(1);
  g.goal_id = 42;
  g.kind = GoalKind::kHome;
  g.has_goal = true;
  g.goal_m = {3.5, -2};
  std::string error;
  const auto back = from_msg(to_msg(g), &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->goal_id, 42u);
  EXPECT_EQ(back->kind, GoalKind::kHome);
  EXPECT_EQ(back->goal_m, Eigen::Vector2d(3.5, -2));
  cairn_msgs::ExplorationGoal bad = to_msg(g);
  bad.kind(9);
  EXPECT_FALSE(from_msg(bad, &error));
  EXPECT_NE(error.find("unknown kind 9"), std::string::npos) << error;
  bad = to_msg(g);
  bad.y_m(INFINITY);
  EXPECT_FALSE(from_msg(bad, &error));
  bad = to_msg(g);
  bad.x_m(1e9);
  EXPECT_FALSE(from_msg(bad, &error));
  EXPECT_NE(error.find("100 km"), std::string::npos) << error;
}

TEST(NavigationConversions, StatusNavigationPartRoundTrips) {
  NavStatus n;
  n.pose = SE2(1, 2, 0.5);
  n.activity = RobotActivity::kReturningToContact;
  n.goal_id = 7;
  n.goal_kind = GoalKind::kExplore;
  n.nav_state = NavState::kStuck;
  n.goal_m = {4, 5};
  n.distance_m = 12.5;
  n.command = {12, CommandState::kFailed, "no path on its map"};
  n.keep_out_version = 6;
  cairn_msgs::RobotStatus m;
  set_nav_status(n, &m);
  std::string error;
  const auto back = nav_status_from(m, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->activity, RobotActivity::kReturningToContact);
  EXPECT_EQ(back->nav_state, NavState::kStuck);
  EXPECT_NEAR(back->pose.yaw(), 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(back->distance_m, 12.5);
  EXPECT_EQ(back->command.seq, 12u);
  EXPECT_EQ(back->command.state, CommandState::kFailed);
  EXPECT_EQ(back->command.note, "no path on its map");
  EXPECT_EQ(back->keep_out_version, 6u);
  m.command_state(40);
  EXPECT_FALSE(nav_status_from(m, &error));
  EXPECT_NE(error.find("command state 40"), std::string::npos) << error;
  set_nav_status(n, &m);
  m.nav_state(77);
  EXPECT_FALSE(nav_status_from(m, &error));
}

TEST(NavigationConversions, TheStatusCarriesThePathAheadAndRefusesABrokenOne) {
  NavStatus n;
  for (int i = 0; i < 40; ++i) n.path_m.emplace_back(0.5 * i, -0.25 * i);  // more than a status carries
  cairn_msgs::RobotStatus m;
  set_nav_status(n, &m);
  std::string error;
  auto back = nav_status_from(m, &error);
  ASSERT_TRUE(back) << error;
  ASSERT_EQ(back->path_m.size(), kMaxStatusPathPoints);
  EXPECT_TRUE(back->path_m[3].isApprox(Eigen::Vector2d(1.5, -0.75)));
  m.path_y_m().pop_back();
  EXPECT_FALSE(nav_status_from(m, &error));
  EXPECT_EQ(error, "status: path of 32 x and 31 y coordinates");
  set_nav_status(n, &m);
  m.path_x_m()[5] = std::nanf("");
  EXPECT_FALSE(nav_status_from(m, &error));
  EXPECT_EQ(error, "status: path point 5 is not finite");
}

TEST(NavigationConversions, OperatorCommandRoundTripsAndBadOnesAreNamed) {
  const OperatorCommand c{RobotId(2), 5, CommandKind::kGoTo, {1.5, -3}};
  std::string error;
  const auto back = from_msg(to_msg(c), &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->robot, RobotId(2));
  EXPECT_EQ(back->seq, 5u);
  EXPECT_EQ(back->kind, CommandKind::kGoTo);
  EXPECT_EQ(back->goal_m, Eigen::Vector2d(1.5, -3));
  cairn_msgs::OperatorCommand bad = to_msg(c);
  bad.kind(4);
  EXPECT_FALSE(from_msg(bad, &error));
  EXPECT_NE(error.find("unknown kind 4"), std::string::npos) << error;
  bad = to_msg(c);
  bad.x_m(std::nan(""));
  EXPECT_FALSE(from_msg(bad, &error));
  EXPECT_NE(error.find("non-finite point"), std::string::npos) << error;
  bad = to_msg(c);
  bad.seq(0);
  EXPECT_FALSE(from_msg(bad, &error));
  EXPECT_NE(error.find("seq 0"), std::string::npos) << error;
}

TEST(NavigationConversions, KeepOutAreasRoundTripAndABadOneIsNamed) {
  KeepOutMessage k{RobotId(1), 9, {in_frame({3, {1, 2}, {4, 5}}, SE2(0.5, -1, 0.3))}};
  std::string error;
  const auto back = from_msg(to_msg(k), &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->robot, RobotId(1));
  EXPECT_EQ(back->version, 9u);
  ASSERT_EQ(back->areas.size(), 1u);
  EXPECT_EQ(back->areas[0].id, 3u);
  for (size_t c = 0; c < 4; ++c) EXPECT_EQ(back->areas[0].corners_m[c], k.areas[0].corners_m[c]);
  cairn_msgs::KeepOutAreas bad = to_msg(k);
  bad.areas()[0].y_m()[2] = std::nan("");
  EXPECT_FALSE(from_msg(bad, &error));
  EXPECT_EQ(error, "keep-out areas: keep-out area 3: a corner is not a finite number");
  bad = to_msg(k);
  bad.robot_id(-1);
  EXPECT_FALSE(from_msg(bad, &error));
  EXPECT_NE(error.find("robot_id -1"), std::string::npos) << error;
  k.areas.assign(kMaxKeepOutAreas + 5, k.areas[0]);  // beyond the IDL's bound: the first 64 go
  EXPECT_EQ(to_msg(k).areas().size(), kMaxKeepOutAreas);
}

}  // namespace
}  // namespace cairn::dds
