// The guided search around a link hypothesis (MapperOptions::guided_link): a robot linked at one
// place whose own map drifts away from the others' elsewhere is judged as closures found around the
// hypothesis place it once the rigid placement is refuted. Runs without DDS.
#include <gtest/gtest.h>

#include <cmath>

#include "base_station/core/multi_robot_mapper.h"
#include "base_station/core/synthetic_world_test_util.h"

namespace cairn::base {
namespace {

using testing::along;

/// Keyframes of `path_world` whose front end turns by `yaw_drift_rad_per_m` more than it really
/// turned on every metre after keyframe `from`: the scans are true, the poses bend from there.
std::vector<Keyframe> drifting_after(RobotId robot, const std::vector<SE2>& path_world, size_t from, double yaw_drift_rad_per_m) {
  std::vector<Keyframe> out = testing::make_keyframes(robot, path_world, testing::two_wing_building());
  for (size_t i = from + 1; i < out.size(); ++i) {
    const SE2 step = path_world[i - 1].between(path_world[i]);
    out[i].T_prev_this = SE2(step.x(), step.y(), step.yaw() + yaw_drift_rad_per_m * step.translation().norm());
    out[i].T_local_base = out[i - 1].T_local_base * out[i].T_prev_this;
    // An honest front end: its heading uncertainty covers the drift (a third of a sigma per step).
    out[i].edge_covariance(2, 2) = std::pow(3.0 * yaw_drift_rad_per_m * step.translation().norm(), 2);
  }
  return out;
}

struct Merge {
  MultiRobotMapper mapper;
  std::vector<LinkEvent> events;
};

/// Robot 0 (the anchor, exact) tours wing W; robot 1 tours room A, then drives the corridor east
/// with its heading drifting. All of robot 1's keyframes reach the base before it is judged (a
/// backlog after a radio outage).
Merge run(const MapperOptions& options, const std::vector<SE2>& p1, size_t drift_from, double drift) {
  Merge out{MultiRobotMapper(options), {}};
  for (const Keyframe& kf : testing::make_keyframes(RobotId(0), along(testing::west_route(0)), testing::two_wing_building())) {
    out.mapper.add_keyframe(kf);
  }
  out.mapper.optimize();
  for (const Keyframe& kf : drifting_after(RobotId(1), p1, drift_from, drift)) out.mapper.add_keyframe(kf);
  for (int i = 0; i < 20 && (i < 3 || out.mapper.refinement_pending()); ++i) {
    const OptimizeResult r = out.mapper.optimize();
    out.events.insert(out.events.end(), r.link_events.begin(), r.link_events.end());
  }
  return out;
}

TEST(MergerGuidedLink, ARobotWhoseMapDriftsAwayFromTheLinkIsCheckedAsTheGuidedClosuresPlaceIt) {
  const std::vector<SE2> p1 = along({{1.5, 6}, {4.5, 6.5}, {3, 5}, {1.5, 6}, {3, 5}, {3, 1}, {11, 1}});
  size_t drift_from = 0;  // robot 1's heading drifts once it is back in the corridor: 1 deg/m
  while (p1[drift_from].y() > 1.5) ++drift_from;
  const double drift = 1.0 * M_PI / 180.0;

  // Placed rigidly by its clique, robot 1's corridor lies in robot 0's walls further east: refuted.
  MapperOptions rigid;
  rigid.guided_link.enabled = false;
  const Merge without = run(rigid, p1, drift_from, drift);
  ASSERT_FALSE(without.events.empty());
  EXPECT_FALSE(without.mapper.linked(RobotId(1))) << "the drift no longer refutes a rigid placement: the test lost its point";
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
  double worst_m = 0.0, front_end_worst_m = 0.0;
  const std::vector<Keyframe> k1 = drifting_after(RobotId(1), p1, drift_from, drift);
  const SE2 T_world_local1 = p1.front();
  for (size_t i = 0; i < p1.size(); ++i) {
    const Eigen::Vector2d truth = (T_global_world * p1[i]).translation();
    worst_m = std::max(worst_m, (with.mapper.global_pose({RobotId(1), int32_t(i)})->translation() - truth).norm());
    front_end_worst_m = std::max(front_end_worst_m, ((T_global_world * T_world_local1 * k1[i].T_local_base).translation() - truth).norm());
  }
  EXPECT_LT(worst_m, 0.1) << "front end placed by its true start: " << front_end_worst_m << " m";
  EXPECT_GT(front_end_worst_m, 0.5);
}

}  // namespace
}  // namespace cairn::base
