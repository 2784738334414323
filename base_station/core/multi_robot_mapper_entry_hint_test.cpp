// Entry hints: roughly where a robot entered bounds its link search. A right tight hint is searched
// around (robot_linker_hints.cpp) and links a robot whose Scan Context closures are too local for
// the spread rule; the hint alone never waives that rule; a hint wrong by more than its sigma never
// causes a wrong link.
#include <gtest/gtest.h>

#include "base_station/core/multi_robot_mapper.h"
#include "base_station/core/synthetic_world_test_util.h"

namespace cairn::base {
namespace {

constexpr double kDeg = M_PI / 180.0;

/// Robot 0 maps the room along the long path; robot 1 retraces only its first `keyframes` keyframes.
MultiRobotMapper two_robots(size_t keyframes, const std::optional<EntryHint>& hint, std::vector<SE2>* p0,
                            std::vector<SE2>* p1, const MapperOptions& options = {}) {
  MultiRobotMapper mapper(options);
  const auto walls = testing::room_walls();
  *p0 = testing::long_path();
  *p1 = testing::retrace(*p0);
  p1->resize(keyframes);
  if (hint) EXPECT_TRUE(mapper.set_entry_hint(RobotId(1), *hint));
  for (const Keyframe& k : testing::make_keyframes(RobotId(0), *p0, walls)) mapper.add_keyframe(k);
  for (const Keyframe& k : testing::make_keyframes(RobotId(1), *p1, walls)) mapper.add_keyframe(k);
  for (int i = 0; i < 3; ++i) mapper.optimize();
  return mapper;
}

/// Robot 1's true start in the global frame (robot 0's local frame).
SE2 true_start(const std::vector<SE2>& p0, const std::vector<SE2>& p1) { return p0[0].inverse() * p1[0]; }

double placement_error_m(const MultiRobotMapper& mapper, const std::vector<SE2>& p0, const std::vector<SE2>& p1) {
  double worst = 0;
  for (size_t i = 0; i < p1.size(); ++i) {
    const SE2 truth = p0[0].inverse() * p1[i];
    worst = std::max(worst,
                     (mapper.global_pose(KeyframeId{RobotId(1), int(i)})->translation() - truth.translation()).norm());
  }
  return worst;
}

TEST(EntryHint, ARightTightHintIsSearchedAroundAndLinksARobotWhoseClosuresAreTooLocal) {
  std::vector<SE2> p0, p1;
  const MultiRobotMapper without = two_robots(4, std::nullopt, &p0, &p1);
  EXPECT_FALSE(without.linked(RobotId(1))) << "4 keyframes span less than min_link_spread_m";
  // The team's guess: 0.3 m and 5 deg off the truth, with sigmas 0.5 m and 10 deg.
  const SE2 start = true_start(p0, p1) * SE2(0.2, -0.22, 5 * kDeg);
  const MultiRobotMapper with = two_robots(4, EntryHint{start, 0.5, 10 * kDeg}, &p0, &p1);
  ASSERT_TRUE(with.linked(RobotId(1)));
  EXPECT_LT(placement_error_m(with, p0, p1), 0.1);
}

TEST(EntryHint, ATightHintThatConfirmsTheClosuresStandsInForTheirSpread) {
  std::vector<SE2> p0, p1;
  const MultiRobotMapper probe = two_robots(1, std::nullopt, &p0, &p1);
  MapperOptions no_search;  // Scan Context's closures only
  no_search.entry_hint_search.enabled = false;
  const SE2 start = true_start(p0, p1) * SE2(0.2, -0.22, 5 * kDeg);
  const MultiRobotMapper tight = two_robots(4, EntryHint{start, 0.5, 10 * kDeg}, &p0, &p1, no_search);
  ASSERT_TRUE(tight.linked(RobotId(1)));
  EXPECT_LT(placement_error_m(tight, p0, p1), 0.1);
  // A loose hint (1 m / 20 deg): its gate passes look-alike places metres off, so the closures from
  // one spot wait for closures from elsewhere as without a hint; nor is it searched around.
  for (const MapperOptions& options : {no_search, MapperOptions{}}) {
    const MultiRobotMapper loose = two_robots(4, EntryHint{true_start(p0, p1), 1.0, 20 * kDeg}, &p0, &p1, options);
    EXPECT_FALSE(loose.linked(RobotId(1)));
    EXPECT_GT(loose.link_stats().deferred_spread, 0);
  }
}

TEST(EntryHint, RobotsSideBySideInALookAlikeCorridorAreNotLinkedAPeriodOff) {
  // A corridor with a pillar every 1.25 m: robot 1 starts one period ahead of robot 0, and both
  // turn on the spot, so their scans match with no offset at all (a look-alike spot 1.25 m off,
  // which the hint's gate passes at 0.5 m sigma). The hint must not let that clique through; a
  // link, if any, is the right one.
  constexpr double kPeriod = 1.25;
  std::vector<testing::Segment> walls = {{{-40, 0}, {60, 0}}, {{-40, 2}, {60, 2}}};
  for (double x = -40; x <= 60; x += kPeriod) walls.push_back({{x, 0}, {x, 0.3}});
  const auto turning = [](double x) {
    std::vector<SE2> path;
    for (int k = 0; k <= 6; ++k) path.emplace_back(x, 1.0, k * 15 * kDeg);
    return path;
  };
  const std::vector<SE2> p0 = turning(10.0 + 0.4), p1 = turning(10.0 + 0.4 + kPeriod);
  MapperOptions no_search;
  no_search.entry_hint_search.enabled = false;
  MultiRobotMapper mapper(no_search);
  const SE2 truth = p0[0].inverse() * p1[0];
  ASSERT_TRUE(mapper.set_entry_hint(RobotId(1), EntryHint{truth * SE2(0.2, -0.2, 3 * kDeg), 0.5, 10 * kDeg}));
  for (const Keyframe& k : testing::make_keyframes(RobotId(0), p0, walls)) mapper.add_keyframe(k);
  for (const Keyframe& k : testing::make_keyframes(RobotId(1), p1, walls)) mapper.add_keyframe(k);
  for (int i = 0; i < 3; ++i) mapper.optimize();
  ASSERT_GT(mapper.loop_closer_stats().accepted, 2) << "the look-alike closures this test is about";
  if (mapper.linked(RobotId(1))) EXPECT_LT(placement_error_m(mapper, p0, p1), 0.3) << "a period off";
}

TEST(EntryHint, AHintWrongByMoreThanItsSigmaNeverCausesAWrongLink) {
  std::vector<SE2> p0, p1;
  // 3 m and 30 deg wrong, sigma 0.5 m: the true closures contradict it.
  const MultiRobotMapper probe = two_robots(1, std::nullopt, &p0, &p1);
  const SE2 wrong = true_start(p0, p1) * SE2(2.1, 2.1, 30 * kDeg);
  const MultiRobotMapper mapper = two_robots(14, EntryHint{wrong, 0.5, 10 * kDeg}, &p0, &p1);
  EXPECT_GT(mapper.link_stats().hint_refused, 0);
  if (mapper.linked(RobotId(1))) EXPECT_LT(placement_error_m(mapper, p0, p1), 0.1) << "a link must be the right one";
  // And the hint alone never places the robot.
  EXPECT_TRUE(mapper.global_trajectory(RobotId(1)).empty() || mapper.linked(RobotId(1)));
}

TEST(EntryHint, BadHintsAreRefusedAndNothingChanges) {
  MultiRobotMapper mapper;
  EXPECT_FALSE(mapper.set_entry_hint(RobotId(1), EntryHint{SE2(std::nan(""), 0, 0), 0.5, 0.1}));
  EXPECT_FALSE(mapper.set_entry_hint(RobotId(1), EntryHint{SE2(), 0.0, 0.1}));
  EXPECT_FALSE(mapper.set_entry_hint(RobotId(1), EntryHint{SE2(), 0.5, -1.0}));
  EXPECT_FALSE(mapper.set_entry_hint(RobotId(), EntryHint{SE2(), 0.5, 0.1}));
  EXPECT_TRUE(mapper.data().entry_hints.empty());
}

}  // namespace
}  // namespace cairn::base
