// The guided search around a link hypothesis (MapperOptions::guided_link): a robot linked at one
// place whose own map drifts away from the others' elsewhere is judged as closures found around the
// hypothesis place it once the rigid placement is refuted. Runs without DDS.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "base_station/core/multi_robot_mapper.h"
#include "base_station/core/synthetic_world_test_util.h"

namespace cairn::base {
namespace {

using testing::along;

/// Robot keyframes through the two-wing building drifting between keyframes `from` and `until`
/// (testing::drifting_keyframes), from an honest front end: its heading uncertainty covers the
/// drift (a third of a sigma per step).
std::vector<Keyframe> drifting_after(RobotId robot, const std::vector<SE2>& path_world, size_t from,
                                     double yaw_drift_rad_per_m, size_t until = SIZE_MAX) {
  std::vector<Keyframe> out =
      testing::drifting_keyframes(robot, path_world, testing::two_wing_building(), yaw_drift_rad_per_m, from, until);
  for (size_t i = from + 1; i < out.size(); ++i) {
    const double step_m = path_world[i - 1].between(path_world[i]).translation().norm();
    out[i].edge_covariance(2, 2) = std::pow(3.0 * yaw_drift_rad_per_m * step_m, 2) + 1e-6;
  }
  return out;
}

struct Merge {
  MultiRobotMapper mapper;
  std::vector<LinkEvent> events;
};

/// The anchor (exact, `anchor`) tours wing W; the new robot (`other`) tours room A, then drives
/// the corridor east with its heading drifting. All of the new robot's keyframes reach the base
/// before it is judged (a backlog after a radio outage).
/// Closures to the robots' first keyframes are off (StartClosureOptions): the synthetic drift is
/// all front end over exact scans, so they would measure and undo the part of it near the new
/// robot's start, and these tests need its map to drift.
Merge run(MapperOptions options, const std::vector<SE2>& p1, size_t drift_from, double drift,
          RobotId anchor = RobotId(0), RobotId other = RobotId(1), size_t drift_until = SIZE_MAX) {
  options.start_closures.every_keyframes = 0;
  Merge out{MultiRobotMapper(options), {}};
  for (const Keyframe& kf :
       testing::make_keyframes(anchor, along(testing::west_route(0)), testing::two_wing_building())) {
    out.mapper.add_keyframe(kf);
  }
  out.mapper.optimize();
  for (const Keyframe& kf : drifting_after(other, p1, drift_from, drift, drift_until)) out.mapper.add_keyframe(kf);
  for (int i = 0; i < 20 && (i < 3 || out.mapper.refinement_pending()); ++i) {
    const OptimizeResult r = out.mapper.optimize();
    out.events.insert(out.events.end(), r.link_events.begin(), r.link_events.end());
  }
  return out;
}

/// Worst distance of `robot`'s merged keyframes from its true path `p` (global frame = the anchor's
/// local frame, whose origin is the start of wing W's route).
double worst_error_m(const MultiRobotMapper& mapper, RobotId robot, const std::vector<SE2>& p) {
  const SE2 T_global_world = along(testing::west_route(0)).front().inverse();
  double worst_m = 0.0;
  for (size_t i = 0; i < p.size(); ++i) {
    const Eigen::Vector2d truth = (T_global_world * p[i]).translation();
    worst_m = std::max(worst_m, (mapper.global_pose({robot, int32_t(i)})->translation() - truth).norm());
  }
  return worst_m;
}

TEST(MultiRobotMapperGuidedLink, ARobotWhoseMapDriftsAwayFromTheLinkIsCheckedAsTheGuidedClosuresPlaceIt) {
  const std::vector<SE2> p1 = along({{1.5, 6}, {4.5, 6.5}, {3, 5}, {1.5, 6}, {3, 5}, {3, 1}, {11, 1}});
  size_t drift_from = 0;  // robot 1's heading drifts once it is back in the corridor: 1 deg/m
  while (p1[drift_from].y() > 1.5) ++drift_from;
  const double drift = 1.0 * M_PI / 180.0;

  // Placed rigidly by its clique, robot 1's corridor lies in robot 0's walls further east: refuted.
  MapperOptions rigid;
  rigid.guided_link.enabled = false;
  const Merge without = run(rigid, p1, drift_from, drift);
  ASSERT_FALSE(without.events.empty());
  EXPECT_FALSE(without.mapper.linked(RobotId(1)))
      << "the drift no longer refutes a rigid placement: the test lost its point";
  EXPECT_GT(without.events.front().contradiction_ratio, MapConsistencyOptions().max_contradiction_ratio);

  // Placed by the closures found around the hypothesis, the maps agree; with them in the graph the
  // merged map follows the scans, not robot 1's drifting front end.
  const Merge with = run(MapperOptions{}, p1, drift_from, drift);
  ASSERT_TRUE(with.mapper.linked(RobotId(1)));
  const LinkEvent& link = with.events.front();
  EXPECT_TRUE(link.accepted) << link.reason;
  EXPECT_GE(link.guided.size(), 5u);
  EXPECT_LT(link.contradiction_ratio, 0.01);
  const SE2 T_global_world = along(testing::west_route(0)).front().inverse();
  double front_end_worst_m = 0.0;
  const std::vector<Keyframe> k1 = drifting_after(RobotId(1), p1, drift_from, drift);
  for (size_t i = 0; i < p1.size(); ++i) {
    const Eigen::Vector2d truth = (T_global_world * p1[i]).translation();
    front_end_worst_m =
        std::max(front_end_worst_m, ((T_global_world * p1.front() * k1[i].T_local_base).translation() - truth).norm());
  }
  const double worst_m = worst_error_m(with.mapper, RobotId(1), p1);
  EXPECT_LT(worst_m, 0.1) << "front end placed by its true start: " << front_end_worst_m << " m";
  EXPECT_GT(front_end_worst_m, 0.5);
}

TEST(MultiRobotMapperGuidedLink, TheNewRobotMayHaveTheLowerId) {
  // Robot 1 is the anchor and robot 0 the newcomer: the hypothesis is judged from the placed side
  // (the closures reversed). Robot 0 starts at the corridor's east end and drifts on its way to
  // room A, where the clique places it: its first keyframe, the tentative graph's lowest id, is
  // off in the rigid placement and must not be held there.
  const std::vector<SE2> p0 = along({{11, 1}, {3, 1}, {3, 5}, {1.5, 6}, {4.5, 6.5}, {3, 5}, {1.5, 6}});
  size_t room = 0;  // drifts until it enters room A
  while (p0[room].y() < 2.5) ++room;
  const Merge merge = run(MapperOptions{}, p0, 0, 1.0 * M_PI / 180.0, RobotId(1), RobotId(0), room);
  ASSERT_TRUE(merge.mapper.linked(RobotId(0)));
  ASSERT_FALSE(merge.events.empty());
  EXPECT_GE(merge.events.front().guided.size(), 5u);
  EXPECT_GE(merge.events.front().rigid_contradiction_ratio, 0.0)
      << "the rigid placement passed: the test lost its point";
  EXPECT_LT(worst_error_m(merge.mapper, RobotId(0), p0), 0.1);
}

}  // namespace
}  // namespace cairn::base
