#include "base_station/core/active_linking.h"

#include <gtest/gtest.h>

namespace cairn::base {
namespace {

StampNs at(double s) { return sec_to_ns(s); }

const RobotId kA(0), kB(1), kC(2);

/// Robot B entered 20 m east of the anchor, facing west (its hint), and is now `x_local_m` along
/// its own x axis (westward in the world).
UnlinkedRobot robot_b(double x_local_m, bool hinted = true) {
  UnlinkedRobot u;
  u.robot = kB;
  u.first_keyframe_ns = at(0);  // mission time starts at 0: a first keyframe at 0 counts
  u.pose_local = SE2(x_local_m, 0, 0);
  if (hinted) u.hypothesis = LinkHypothesis{SE2(20, 0, M_PI), "entry hint"};
  return u;
}

TEST(ActiveLinking, AnUnlinkedRobotWithAHypothesisIsSentToMeetTheNearestPlacedTeammateAfterTheSetTime) {
  ActiveLinker linker;  // after 5 s
  const std::map<RobotId, Eigen::Vector2d> placed{{kA, {2, 0}}, {kC, {30, 15}}};
  EXPECT_TRUE(linker.update({robot_b(0)}, placed, at(4)).empty()) << "not before after_s";
  const auto events = linker.update({robot_b(1)}, placed, at(6.5));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, MeetingEvent::Kind::kStarted);
  const Meeting& m = linker.meetings().at(kB);
  EXPECT_EQ(m.teammate, kA) << "A is 17 m from B's guessed position, C 18.6 m";
  EXPECT_NEAR(m.distance_m, 17.0, 1e-9);
  // B drives west toward 1.5 m short of A (x = 3.5), a leg of at most 10 m at a time: x = 9 in the
  // world, 11 m along its own x axis; A likewise east, to x = 12.
  EXPECT_TRUE(m.robot_goal_global_m.isApprox(Eigen::Vector2d(9, 0))) << m.robot_goal_global_m.transpose();
  EXPECT_TRUE(m.robot_goal_local_m.isApprox(Eigen::Vector2d(11, 0))) << m.robot_goal_local_m.transpose();
  ASSERT_TRUE(m.teammate_goal_m);
  EXPECT_TRUE(m.teammate_goal_m->isApprox(Eigen::Vector2d(12, 0))) << m.teammate_goal_m->transpose();
  EXPECT_EQ(linker.moving_teammates(), std::vector<RobotId>{kA});
  // As they close in, the goals follow; once within met_m (2.5 m) both stop where they are, facing
  // each other, and stay there.
  linker.update({robot_b(8)}, {{kA, {8, 0}}, {kC, {30, 15}}}, at(12));  // 4 m apart
  EXPECT_FALSE(linker.meetings().at(kB).met_ns);
  EXPECT_TRUE(linker.meetings().at(kB).robot_goal_global_m.isApprox(Eigen::Vector2d(9.5, 0)));
  linker.update({robot_b(9.5)}, {{kA, {8, 0}}, {kC, {30, 15}}}, at(14));
  ASSERT_TRUE(linker.meetings().at(kB).met_ns);
  linker.update({robot_b(9.6)}, {{kA, {8.5, 0}}, {kC, {30, 15}}}, at(15));
  EXPECT_TRUE(linker.meetings().at(kB).robot_goal_global_m.isApprox(Eigen::Vector2d(10.5, 0)));
  EXPECT_TRUE(linker.meetings().at(kB).robot_goal_local_m.isApprox(Eigen::Vector2d(9.5, 0)));
  ASSERT_TRUE(linker.meetings().at(kB).teammate_goal_m);
  EXPECT_TRUE(linker.meetings().at(kB).teammate_goal_m->isApprox(Eigen::Vector2d(8, 0)));
  EXPECT_EQ(linker.moving_teammates(), std::vector<RobotId>{kA}) << "held out of the exploration plan";
  // Linked: the meeting ends well.
  const auto linked = linker.update({}, placed, at(16));
  ASSERT_EQ(linked.size(), 1u);
  EXPECT_EQ(linked[0].kind, MeetingEvent::Kind::kLinked);
  EXPECT_TRUE(linker.meetings().empty());
  EXPECT_EQ(linker.stats().started, 1);
  EXPECT_EQ(linker.stats().linked, 1);
}

TEST(ActiveLinking, WithoutAHypothesisOrAPlacedTeammateNobodyIsSent) {
  ActiveLinker linker;
  EXPECT_TRUE(linker.update({robot_b(0, false)}, {{kA, {2, 0}}}, at(30)).empty());
  EXPECT_TRUE(linker.update({robot_b(0)}, {}, at(30)).empty());
  EXPECT_TRUE(linker.meetings().empty());
  ActiveLinkingOptions disabled;
  disabled.enabled = false;
  ActiveLinker off(disabled);
  EXPECT_TRUE(off.update({robot_b(0)}, {{kA, {2, 0}}}, at(30)).empty());
}

TEST(ActiveLinking, AMeetingThatBringsNoLinkIsGivenUpAndNotTriedAgainForAWhile) {
  ActiveLinker linker;  // met_wait 15 s, retry 60 s
  const std::map<RobotId, Eigen::Vector2d> placed{{kA, {2, 0}}};
  ASSERT_EQ(linker.update({robot_b(0)}, placed, at(10)).size(), 1u);
  linker.update({robot_b(16)}, placed, at(20));  // 2 m apart under the (wrong) guess: met
  ASSERT_TRUE(linker.meetings().at(kB).met_ns);
  EXPECT_TRUE(linker.update({robot_b(16)}, placed, at(34)).empty());
  const auto failed = linker.update({robot_b(16)}, placed, at(36));
  ASSERT_EQ(failed.size(), 1u);
  EXPECT_EQ(failed[0].kind, MeetingEvent::Kind::kFailed);
  EXPECT_NE(failed[0].why.find("verified"), std::string::npos) << failed[0].why;
  EXPECT_TRUE(linker.update({robot_b(0)}, placed, at(90)).empty()) << "resting until 96 s";
  const auto again = linker.update({robot_b(0)}, placed, at(97));
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0].kind, MeetingEvent::Kind::kStarted);
  // Never met: given up after max_meeting_s.
  EXPECT_TRUE(linker.update({robot_b(0)}, placed, at(97 + 89)).empty());
  const auto late = linker.update({robot_b(0)}, placed, at(97 + 91));
  ASSERT_EQ(late.size(), 1u);
  EXPECT_EQ(late[0].kind, MeetingEvent::Kind::kFailed);
  EXPECT_EQ(linker.stats().failed, 2);
}

TEST(ActiveLinking, AGoalEitherSideCannotReachEndsTheMeeting) {
  ActiveLinker linker;
  const std::map<RobotId, Eigen::Vector2d> placed{{kA, {2, 0}}};
  linker.update({robot_b(0)}, placed, at(10));
  EXPECT_FALSE(linker.goal_failed(kC, at(11))) << "no meeting of C's";
  const auto failed = linker.goal_failed(kA, at(11));
  ASSERT_TRUE(failed);
  EXPECT_EQ(failed->meeting.robot, kB);
  EXPECT_TRUE(linker.meetings().empty());
}

TEST(ActiveLinking, AGoalGivenUpByARobotLinkedMeanwhileEndsTheMeetingLinkedNotFailed) {
  ActiveLinker linker;
  const std::map<RobotId, Eigen::Vector2d> placed{{kA, {2, 0}}};
  linker.update({robot_b(0)}, placed, at(10));
  ASSERT_EQ(linker.meetings().size(), 1u);
  // B was linked (say by the search around its hint) and gave up its goal before the next update.
  const auto b_placed = [](RobotId r) { return r == kB; };
  EXPECT_FALSE(linker.goal_failed(kB, at(11), b_placed));
  EXPECT_FALSE(linker.goal_failed(kA, at(11), b_placed));
  const auto events = linker.update({}, {{kA, {2, 0}}, {kB, {0, 0}}}, at(12));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events.front().kind, MeetingEvent::Kind::kLinked);
  EXPECT_EQ(linker.stats().linked, 1);
}

TEST(ActiveLinking, OneTeammateDrivesToOneMeetingAtATimeTheOtherRobotDrivesToItAlone) {
  ActiveLinker linker;
  UnlinkedRobot c = robot_b(0);
  c.robot = kC;
  c.hypothesis->T_global_local = SE2(2, 20, -M_PI / 2);  // entered 20 m north of A, facing south
  const auto events = linker.update({robot_b(0), c}, {{kA, {2, 0}}}, at(10));
  ASSERT_EQ(events.size(), 2u);
  EXPECT_TRUE(linker.meetings().at(kB).teammate_goal_m);
  EXPECT_FALSE(linker.meetings().at(kC).teammate_goal_m);
  EXPECT_TRUE(linker.meetings().at(kC).robot_goal_global_m.isApprox(Eigen::Vector2d(2, 10)));  // 10 m of 18.5
  EXPECT_EQ(linker.moving_teammates(), std::vector<RobotId>{kA});
  // B links: A is free, and now drives toward C.
  linker.update({c}, {{kA, {2, 0}}}, at(12));
  EXPECT_TRUE(linker.meetings().at(kC).teammate_goal_m);
}

TEST(ActiveLinking, AMeetingSwitchesToAMuchNearerPlacedRobotAndAFailedPairRestsWhileOthersMayMeet) {
  ActiveLinker linker;
  linker.update({robot_b(0)}, {{kA, {2, 0}}}, at(10));
  ASSERT_EQ(linker.meetings().at(kB).teammate, kA);
  // C is placed 5 m from B's guessed position (A is 17 m away): B meets C instead.
  linker.update({robot_b(1)}, {{kA, {2, 0}}, {kC, {19, 5}}}, at(12));
  EXPECT_EQ(linker.meetings().at(kB).teammate, kC);
  // Not for a little nearer: C at 0.8 of A's distance is not worth the turn.
  ActiveLinker steady;
  steady.update({robot_b(0)}, {{kA, {2, 0}}}, at(10));
  steady.update({robot_b(1)}, {{kA, {2, 0}}, {kC, {19, 14}}}, at(12));
  EXPECT_EQ(steady.meetings().at(kB).teammate, kA);
  // C could not drive to B: the pair B-C rests, and B is sent to A at once.
  ASSERT_TRUE(linker.goal_failed(kC, at(13)));
  const auto events = linker.update({robot_b(1)}, {{kA, {2, 0}}, {kC, {19, 5}}}, at(14));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, MeetingEvent::Kind::kStarted);
  EXPECT_EQ(linker.meetings().at(kB).teammate, kA);
  // ...and stays with A, however near C is, while the pair rests.
  linker.update({robot_b(2)}, {{kA, {2, 0}}, {kC, {19, 5}}}, at(20));
  EXPECT_EQ(linker.meetings().at(kB).teammate, kA);
}

TEST(ActiveLinking, ARobotAlreadyNearItsTeammateUnderTheHypothesisIsNotSent) {
  ActiveLinker linker;
  EXPECT_TRUE(linker.update({robot_b(0)}, {{kA, {19, 1}}}, at(10)).empty());
}

TEST(ActiveLinking, CloseWithAWallBetweenThemIsNotMet) {
  // A wall along x = 10 (global): nobody on one side sees the other side.
  const LineOfSight wall_at_10 = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a.x() - 10) * (b.x() - 10) > 0;
  };
  ActiveLinker linker;
  EXPECT_EQ(linker.update({robot_b(9)}, {{kA, {9, 1}}}, at(10), wall_at_10).size(), 1u)
      << "B (at x = 11) is 2.2 m from A, but behind the wall: sent";
  linker.update({robot_b(9)}, {{kA, {9, 1}}}, at(12), wall_at_10);
  EXPECT_FALSE(linker.meetings().at(kB).met_ns);
  linker.update({robot_b(10.5)}, {{kA, {9, 1}}}, at(14), wall_at_10);  // B came round: x = 9.5
  EXPECT_TRUE(linker.meetings().at(kB).met_ns);
}

}  // namespace
}  // namespace cairn::base
