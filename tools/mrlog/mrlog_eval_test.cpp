#include "tools/mrlog/mrlog_eval.h"

#include <gtest/gtest.h>

namespace cairn::mrlog {
namespace {

/// Two robots that entered at different places of the world.
MultiRobotLog two_robots() {
  MultiRobotLog log;
  log.robot_data(RobotId(0)).truth.push_back({0, SE2(3.0, -1.0, 0.5)});
  log.robot_data(RobotId(1)).truth.push_back({0, SE2(10.0, 4.0, -1.0)});
  return log;
}

void expect_near(const SE2& a, const SE2& b) {
  EXPECT_NEAR(a.x(), b.x(), 1e-9);
  EXPECT_NEAR(a.y(), b.y(), 1e-9);
  EXPECT_NEAR(a.yaw(), b.yaw(), 1e-9);
}

TEST(MrlogEval, WithoutAGivenStartTheGlobalFrameIsTheAnchorRobotsStart) {
  const MultiRobotLog log = two_robots();
  const nlohmann::json summary = {{"robots", {{{"id", 0}, {"anchor", false}}, {{"id", 1}, {"anchor", true}}}}};
  const auto f = global_frame_of(log, summary);
  ASSERT_TRUE(f);
  expect_near(f->T_global_world * SE2(10.0, 4.0, -1.0), SE2());  // robot 1 starts at the global origin
  EXPECT_EQ(f->description, "robot 1's start");
  // No summary at all: the lowest id.
  const auto g = global_frame_of(log, nlohmann::json());
  ASSERT_TRUE(g);
  expect_near(g->T_global_world * SE2(3.0, -1.0, 0.5), SE2());
}

TEST(MrlogEval, AGivenStartPutsTheRobotWhereItWasGivenNotAtTheOrigin) {
  // `cairn_base --start 1,10,4,-1`: the world poses themselves, so global == world (the bug was a
  // 7.6 m error on the corridor world from taking the anchor's start as the origin anyway).
  const MultiRobotLog log = two_robots();
  const nlohmann::json summary = {{"robots",
                                   {{{"id", 0}, {"anchor", true}},
                                    {{"id", 1}, {"given_start", {{"x_m", 10.0}, {"y_m", 4.0}, {"yaw_rad", -1.0}}}}}}};
  const auto f = global_frame_of(log, summary);
  ASSERT_TRUE(f);
  expect_near(f->T_global_world, SE2());
  EXPECT_EQ(f->description, "the start given for robot 1");
  // A start given in another frame: that robot sits where it was given.
  nlohmann::json shifted = summary;
  shifted["robots"][1]["given_start"] = {{"x_m", 0.0}, {"y_m", 0.0}, {"yaw_rad", 0.0}};
  const auto g = global_frame_of(log, shifted);
  ASSERT_TRUE(g);
  expect_near(g->T_global_world * SE2(10.0, 4.0, -1.0), SE2());
}

TEST(MrlogEval, NoReferenceForTheRobotThatFixesTheFrameIsNoFrame) {
  MultiRobotLog log;
  log.robot_data(RobotId(0));  // no TRUTH records
  EXPECT_FALSE(global_frame_of(log, nlohmann::json()));
  EXPECT_FALSE(global_frame_of(MultiRobotLog(), nlohmann::json()));
  // A malformed given_start is ignored, not trusted.
  const MultiRobotLog two = two_robots();
  const nlohmann::json bad = {{"robots", {{{"id", 1}, {"given_start", {{"x_m", "ten"}}}}}}};
  const auto f = global_frame_of(two, bad);
  ASSERT_TRUE(f);
  EXPECT_EQ(f->description, "robot 0's start");
}

}  // namespace
}  // namespace cairn::mrlog
