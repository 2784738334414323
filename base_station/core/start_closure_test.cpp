// Closures from a robot's first keyframe (StartClosureOptions): a front end whose first edge is a
// degree off (the local SLAM's start-up aliasing) turns everything after it about the robot's
// start; the first scan verified in the local maps of later keyframes puts the heading back.
#include <gtest/gtest.h>

#include "base_station/core/multi_robot_mapper.h"
#include "base_station/core/synthetic_world_test_util.h"

namespace cairn::base {
namespace {

const RobotId kR0(0);
constexpr double kDeg = M_PI / 180.0;

std::vector<SE2> path() { return testing::along({{1.5, 1.0}, {4.5, 1.0}, {4.5, 4.5}, {1.5, 4.5}}); }

/// The robot's keyframes as a front end with a 1-degree error in its first edge reports them.
std::vector<Keyframe> turned_after_first(const std::vector<SE2>& truth) {
  std::vector<Keyframe> kfs = testing::make_keyframes(kR0, truth, testing::room_walls());
  const SE2 turn(0, 0, 1.0 * kDeg);  // about the first keyframe (the local frame's origin)
  for (size_t i = 1; i < kfs.size(); ++i) kfs[i].T_local_base = turn * kfs[i].T_local_base;
  kfs[1].T_prev_this = kfs[0].T_local_base.between(kfs[1].T_local_base);
  return kfs;
}

struct Placed {
  /// Over the keyframes from the first start closure on (those before it share out its correction
  /// as their edges' weights say: the first's error is not singled out).
  double worst_yaw_deg = 0;
  double worst_m = 0;  ///< over every keyframe
  int start_closures = 0;
};

Placed merge(const MapperOptions& options) {
  const std::vector<SE2> truth = path();
  MultiRobotMapper mapper(options);
  mapper.set_robot_start(kR0, truth.front());
  for (const Keyframe& kf : turned_after_first(truth)) EXPECT_TRUE(mapper.add_keyframe(kf).stored());
  for (int i = 0; i < 3; ++i) mapper.optimize();
  Placed out;
  for (size_t i = 0; i < truth.size(); ++i) {
    const std::optional<SE2> g = mapper.global_pose(KeyframeId{kR0, int32_t(i)});
    EXPECT_TRUE(g.has_value());
    if (!g) continue;
    if (i >= 8) out.worst_yaw_deg = std::max(out.worst_yaw_deg, std::abs(g->between(truth[i]).yaw()) / kDeg);
    out.worst_m = std::max(out.worst_m, (g->translation() - truth[i].translation()).norm());
  }
  out.start_closures = mapper.link_stats().start_closures;
  return out;
}

TEST(StartClosures, TheFirstScanPutsBackTheHeadingItsFirstEdgeLost) {
  ASSERT_GE(path().size(), 17u);  // keyframes 8 and 16 lie within 4 m of the first
  MapperOptions off;
  off.start_closures.every_keyframes = 0;
  const Placed without = merge(off);
  EXPECT_EQ(without.start_closures, 0);
  EXPECT_GT(without.worst_yaw_deg, 0.8) << "nothing else measures the first edge's error here";

  const Placed with = merge(MapperOptions{});
  EXPECT_GE(with.start_closures, 2);
  EXPECT_LT(with.worst_yaw_deg, 0.25);
  EXPECT_LT(with.worst_m, 0.03);
}

}  // namespace
}  // namespace cairn::base
