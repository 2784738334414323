// The goal state machine on message time: stuck after stuck_after_s without stuck_progress_m of
// progress (and not before), progress restarts the clock, a new goal's failed plan is unreachable
// at once, re-plans only after max_plan_failures in a row, a boxed-in robot ends stuck, and each
// change carries its reason and stamp.
#include "robot_agent/core/navigation/goal_tracker.h"

#include <gtest/gtest.h>

#include <cmath>

namespace cairn::agent {
namespace {

StampNs at(double s) { return sec_to_ns(s); }

TEST(GoalTracker, StuckAfterTenSecondsWithoutThirtyCentimetresOfProgress) {
  GoalTracker t;
  EXPECT_EQ(t.state(), NavState::kIdle);
  t.start("goal 1");
  EXPECT_EQ(t.state(), NavState::kDriving);
  EXPECT_EQ(t.reason(), "goal 1");
  t.note_pose(at(100.0), {0, 0});
  // Creeping: 0.29 m in 9.9 s is not progress, but not yet stuck either.
  for (int i = 1; i <= 99; ++i) t.note_pose(at(100.0 + 0.1 * i), {0.29 * i / 99.0, 0});
  EXPECT_EQ(t.state(), NavState::kDriving);
  EXPECT_NEAR(t.seconds_without_progress(), 9.9, 1e-6);
  t.note_pose(at(110.0), {0.29, 0});
  EXPECT_EQ(t.state(), NavState::kStuck);
  EXPECT_EQ(t.last_transition().from, NavState::kDriving);
  EXPECT_EQ(t.last_transition().stamp_ns, at(110.0));
  EXPECT_NE(t.reason().find("no progress: moved 0.29 m (< 0.30 m) in 10.0 s"), std::string::npos) << t.reason();
}

TEST(GoalTracker, SwingingBackAndForthIsStuckOnceItLastsHalfAMinute) {
  GoalTracker t;
  t.start("home");
  // 0.85 m to and fro every 4 s: each swing is "progress" for the 10 s test (as seen in the office).
  double s = 0;
  for (; s < 29.9; s += 0.1) {
    t.note_pose(at(s),
                {14.85, 11.65 + 0.85 * (std::fmod(s, 8.0) < 4.0 ? std::fmod(s, 4.0) : 4.0 - std::fmod(s, 4.0)) / 4.0});
  }
  EXPECT_EQ(t.state(), NavState::kDriving);
  t.note_pose(at(30.0), {14.85, 11.65});
  EXPECT_EQ(t.state(), NavState::kStuck);
  EXPECT_NE(t.reason().find("back and forth"), std::string::npos) << t.reason();
  // A robot driving on (0.1 m/s, slowly) is never confined.
  GoalTracker d;
  d.start("far");
  for (double u = 0; u < 60; u += 0.1) d.note_pose(at(u), {0.1 * u, 0});
  EXPECT_EQ(d.state(), NavState::kDriving);
}

TEST(GoalTracker, ProgressRestartsTheClock) {
  GoalTracker t;
  t.start("goal 1");
  t.note_pose(at(0), {0, 0});
  t.note_pose(at(9), {0.31, 0});  // progress at 9 s
  t.note_pose(at(18.9), {0.4, 0});
  EXPECT_EQ(t.state(), NavState::kDriving);
  t.note_pose(at(19.0), {0.4, 0});
  EXPECT_EQ(t.state(), NavState::kStuck);
  // A new goal starts afresh: driving, and the clock waits for its first pose.
  t.start("goal 2");
  EXPECT_EQ(t.state(), NavState::kDriving);
  t.note_pose(at(25), {0.4, 0});
  t.note_pose(at(34.9), {0.4, 0});
  EXPECT_EQ(t.state(), NavState::kDriving);
}

TEST(GoalTracker, AFailedFirstPlanIsUnreachableAtOnce) {
  GoalTracker t;
  t.start("goal 1");
  t.plan_failed(/*first_plan=*/true, /*boxed_in=*/false, "no path from a to b");
  EXPECT_EQ(t.state(), NavState::kUnreachable);
  EXPECT_EQ(t.reason(), "no path from a to b");
}

TEST(GoalTracker, ReplansMustFailThreeTimesInARow) {
  GoalTracker t;
  t.start("goal 1");
  t.plan_failed(false, false, "no path");
  t.plan_failed(false, false, "no path");
  t.plan_succeeded();  // the count restarts
  t.plan_failed(false, false, "no path");
  t.plan_failed(false, false, "no path");
  EXPECT_EQ(t.state(), NavState::kDriving);
  EXPECT_EQ(t.consecutive_failures(), 2);
  t.plan_failed(false, false, "no path");
  EXPECT_EQ(t.state(), NavState::kUnreachable);
  EXPECT_EQ(t.reason(), "re-planning failed 3 times in a row: no path");
}

TEST(GoalTracker, ABoxedInRobotEndsStuckNotUnreachable) {
  GoalTracker t;
  t.start("goal 1");
  t.note_pose(at(0), {0, 0});
  for (int i = 0; i < 10; ++i) t.plan_failed(i == 0, /*boxed_in=*/true, "boxed in: rubble all round");
  EXPECT_EQ(t.state(), NavState::kDriving);
  EXPECT_EQ(t.consecutive_failures(), 0);
  t.note_pose(at(10), {0.05, 0});
  EXPECT_EQ(t.state(), NavState::kStuck);
  EXPECT_NE(t.reason().find("boxed in: rubble all round"), std::string::npos) << t.reason();
}

TEST(GoalTracker, ReachedWinsOverStuckAtTheSameStamp) {
  GoalTracker t;
  t.start("goal 1");
  t.note_pose(at(0), {0, 0});
  t.reached(at(10), "within 0.40 m");  // 10 s without progress, but there
  EXPECT_EQ(t.state(), NavState::kReached);
  EXPECT_EQ(t.reason(), "within 0.40 m");
}

TEST(GoalTracker, ReachedAndCancelledAreStatesWithReasons) {
  GoalTracker t;
  t.reached(at(1), "too early");  // not driving: ignored
  EXPECT_EQ(t.state(), NavState::kIdle);
  EXPECT_EQ(t.transitions(), 0);
  t.start("goal 1");
  t.note_pose(at(2), {1, 1});
  t.reached(at(5), "within 0.40 m");
  EXPECT_EQ(t.state(), NavState::kReached);
  EXPECT_EQ(t.last_transition().stamp_ns, at(5));
  t.note_pose(at(100), {1, 1});  // not driving: no stuck
  EXPECT_EQ(t.state(), NavState::kReached);
  t.cancel("cancelled");
  EXPECT_EQ(t.state(), NavState::kIdle);
  EXPECT_EQ(t.last_transition().from, NavState::kReached);
  EXPECT_EQ(t.transitions(), 3);
  EXPECT_STREQ(to_string(NavState::kUnreachable), "unreachable");
}

}  // namespace
}  // namespace cairn::agent
